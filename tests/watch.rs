//! `dieface watch`: rebuilds on edits in place and on write-then-rename saves (the way
//! vim and VS Code save), on edits of an imported file, keeps the last good output when
//! the script breaks, rebuilds when it is fixed, and exits cleanly on Ctrl-C.
//!
//! Everything is polled with generous timeouts so a loaded CI machine only makes the
//! test slower, never flaky.

use std::io::Read;
#[allow(dead_code)] // shares the helpers of other test crates, uses one
mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const TIMEOUT: Duration = Duration::from_secs(30);

const LIB: &str = "let depth = 30 mm\n";

fn script(half: &str) -> String {
    format!(
        r#"import "lib.die" as lib
let half = {half}
let net = [ [ (i * half, j * half, if i == 1 and j == 1 then lib.depth else 0 mm) for j in range(0, 3) ] for i in range(0, 3) ]
product panel = nurbs_surface(degree: (2, 2), points: net)
let unrelated = 3 deg
"#
    )
}

/// The running watcher, killed when dropped (also when a check fails).
struct Watch {
    child: Child,
    stdout: Arc<Mutex<String>>,
    stderr: Arc<Mutex<String>>,
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn collect(mut from: impl Read + Send + 'static) -> Arc<Mutex<String>> {
    let text = Arc::new(Mutex::new(String::new()));
    let sink = text.clone();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 {
                break;
            }
            sink.lock()
                .expect("lock")
                .push_str(&String::from_utf8_lossy(&buf[..n]));
        }
    });
    text
}

impl Watch {
    fn start(dir: &Path, args: &[&str]) -> Watch {
        let mut child = Command::new(env!("CARGO_BIN_EXE_dieface"))
            .current_dir(dir)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn dieface watch");
        let stdout = collect(child.stdout.take().expect("stdout"));
        let stderr = collect(child.stderr.take().expect("stderr"));
        Watch {
            child,
            stdout,
            stderr,
        }
    }

    fn out(&self) -> String {
        self.stdout.lock().expect("lock").clone()
    }

    fn err(&self) -> String {
        self.stderr.lock().expect("lock").clone()
    }

    /// Sends SIGINT (Ctrl-C) and returns the exit code; panics unless watch stops
    /// within `within`.
    #[cfg(unix)]
    fn interrupt(mut self, within: Duration) -> Option<i32> {
        let status = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status()
            .expect("kill -INT");
        assert!(status.success());
        let sent = Instant::now();
        loop {
            if let Some(s) = self.child.try_wait().expect("wait") {
                return s.code();
            }
            assert!(
                sent.elapsed() < within,
                "watch did not stop within {within:?} of SIGINT"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Polls `cond` until it holds; panics with the watcher's output after the timeout.
    fn wait_for(&self, what: &str, mut cond: impl FnMut(&Watch) -> bool) {
        let start = Instant::now();
        while !cond(self) {
            if start.elapsed() > TIMEOUT {
                panic!(
                    "timed out waiting for {what}\n--- stdout\n{}\n--- stderr\n{}",
                    self.out(),
                    self.err()
                );
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

fn read(p: &Path) -> Option<Vec<u8>> {
    std::fs::read(p).ok()
}

fn project(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("watch")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("lib.die"), LIB).expect("lib");
    std::fs::write(dir.join("part.die"), script("100 mm")).expect("script");
    dir
}

/// Waits until the output differs from `before` (and is complete: the writes are
/// atomic), returns the new bytes.
fn changed(w: &Watch, out: &Path, before: &[u8], what: &str) -> Vec<u8> {
    w.wait_for(what, |_| read(out).is_some_and(|b| b != before));
    read(out).expect("output")
}

#[test]
fn watch_rebuilds_on_saves_keeps_the_last_good_output_and_stops_on_ctrl_c() {
    let dir = project("saves");
    let out = dir.join("panel.obj");
    let script_path = dir.join("part.die");
    let w = Watch::start(
        &dir,
        &["watch", "part.die", "-o", "panel.obj", "--color", "never"],
    );
    w.wait_for("the first build", |w| {
        w.out().contains("built in") && read(&out).is_some()
    });
    w.wait_for("the watch to start", |w| w.err().contains("watching"));
    let first = read(&out).expect("output");

    // 1. An edit in place (same inode).
    std::fs::write(&script_path, script("110 mm")).expect("edit");
    let second = changed(&w, &out, &first, "a rebuild after an edit in place");
    w.wait_for("the rebuild line", |w| w.out().contains("rebuilt in"));
    let line = w
        .out()
        .lines()
        .find(|l| l.starts_with("rebuilt in"))
        .map(str::to_string)
        .expect("line");
    assert!(line.contains("half") && line.contains("panel"), "{line}");
    assert!(
        !line.contains("unrelated"),
        "memoized declarations do not re-run: {line}"
    );

    // 2. Write a new file and rename it over the script (vim, VS Code).
    let tmp = dir.join("part.die.swp");
    std::fs::write(&tmp, script("120 mm")).expect("write temp");
    std::fs::rename(&tmp, &script_path).expect("rename over");
    let third = changed(&w, &out, &second, "a rebuild after write-then-rename");

    // 3. Again, to prove the watch survived the rename (the trap).
    std::fs::write(&tmp, script("125 mm")).expect("write temp");
    std::fs::rename(&tmp, &script_path).expect("rename over");
    let fourth = changed(&w, &out, &third, "a rebuild after a second rename");

    // 4. An edit of the imported file.
    std::fs::write(dir.join("lib.die"), "let depth = 45 mm\n").expect("edit lib");
    let fifth = changed(&w, &out, &fourth, "a rebuild after an import changed");

    // 5. Break the script: the diagnostic is printed, the output stays as it was.
    std::fs::write(&script_path, script("125 mm + 3 deg")).expect("break");
    w.wait_for("the diagnostic", |w| {
        w.err().contains("die::unit_mismatch") && w.err().contains("keeping the last good output")
    });
    assert_eq!(
        read(&out).expect("output"),
        fifth,
        "the last good output is kept"
    );

    // 6. Fix it: a rebuild.
    std::fs::write(&script_path, script("130 mm")).expect("fix");
    changed(&w, &out, &fifth, "a rebuild after the fix");

    // 7. Ctrl-C exits cleanly.
    #[cfg(unix)]
    {
        let code = w.interrupt(TIMEOUT);
        assert_eq!(code, Some(0), "clean exit on Ctrl-C");
    }
}

#[test]
fn watch_starts_from_a_broken_script_and_builds_once_it_is_fixed() {
    let dir = project("broken_start");
    let script_path = dir.join("part.die");
    std::fs::write(&script_path, "let a = 10 mm + 5 deg\n").expect("broken");
    let out = dir.join("panel.glb");
    let w = Watch::start(
        &dir,
        &["watch", "part.die", "-o", "panel.glb", "--color", "never"],
    );
    w.wait_for("the diagnostic", |w| {
        w.err().contains("die::unit_mismatch") && w.err().contains("watching")
    });
    assert!(read(&out).is_none(), "no output from a broken script");
    std::fs::write(&script_path, script("100 mm")).expect("fix");
    w.wait_for("the first output", |_| {
        read(&out).is_some_and(|b| b.starts_with(b"glTF"))
    });
}

/// Two products, so deleting one changes the scene, and a declaration nothing uses.
fn two_products(half: &str) -> String {
    format!(
        r#"import "lib.die" as lib
let half = {half}
let net = [ [ (i * half, j * half, if i == 1 and j == 1 then lib.depth else 0 mm) for j in range(0, 3) ] for i in range(0, 3) ]
product panel = nurbs_surface(degree: (2, 2), points: net)
product tipped = nurbs_surface(degree: (2, 2), points: net) |> tip(about: "x", by: 5 deg)
let unrelated = 3 deg
"#
    )
}

/// What a fresh `dieface build` of the script now in `dir` writes.
fn fresh_build(dir: &Path) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_dieface"))
        .current_dir(dir)
        .args(["build", "part.die", "-o", "fresh.glb", "--color", "never"])
        .output()
        .expect("run dieface build");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    read(&dir.join("fresh.glb")).expect("fresh output")
}

/// Saves `text` as the script and waits until watch's output is byte for byte what a
/// fresh build of it writes.
fn save_and_match(w: &Watch, dir: &Path, out: &Path, text: &str, what: &str) -> Vec<u8> {
    std::fs::write(dir.join("part.die"), text).expect("save");
    let fresh = fresh_build(dir);
    w.wait_for(what, |_| read(out).as_deref() == Some(fresh.as_slice()));
    fresh
}

#[test]
fn watch_output_always_equals_a_fresh_build_of_the_last_good_script() {
    let dir = project("fresh");
    let out = dir.join("panel.glb");
    let script_path = dir.join("part.die");
    std::fs::write(&script_path, two_products("100 mm")).expect("script");
    let w = Watch::start(
        &dir,
        &["watch", "part.die", "-o", "panel.glb", "--color", "never"],
    );
    w.wait_for("the watch to start", |w| w.err().contains("watching"));
    let text = two_products("100 mm");
    save_and_match(&w, &dir, &out, &text, "the first build");

    // 1. Delete a declaration: it leaves the scene, though nothing re-runs.
    let deleted: String = text
        .lines()
        .filter(|l| !l.starts_with("product tipped"))
        .map(|l| format!("{l}\n"))
        .collect();
    save_and_match(&w, &dir, &out, &deleted, "the deleted product to leave");

    // 2. A line above the declarations: every node's extras.line moves.
    let moved = format!("// a comment above everything\n{deleted}");
    save_and_match(&w, &dir, &out, &moved, "the lines to move");

    // 3. An edit of the imported module.
    std::fs::write(dir.join("lib.die"), "let depth = 40 mm\n").expect("edit lib");
    let fresh = fresh_build(&dir);
    w.wait_for("the module's edit", |_| {
        read(&out).as_deref() == Some(fresh.as_slice())
    });

    // 4. A broken save, then a save by truncate-then-write: the momentary empty script
    // is not built, the last good output stays; the written script is built.
    let good = read(&out).expect("output");
    std::fs::write(&script_path, "let broken = \n").expect("break");
    w.wait_for("the diagnostic", |w| {
        w.err().contains("keeping the last good output")
    });
    std::fs::write(&script_path, "").expect("truncate");
    w.wait_for("the empty script's warning", |w| {
        w.err()
            .contains("the script is empty; keeping the last output")
    });
    assert_eq!(
        read(&out).expect("output"),
        good,
        "the empty script wrote nothing"
    );
    save_and_match(
        &w,
        &dir,
        &out,
        &two_products("90 mm"),
        "the script after the truncate",
    );

    // 5. Ctrl-C in the middle of a long rebuild stops at once, leaving the last good
    // output and no temporary file.
    #[cfg(unix)]
    {
        let good = read(&out).expect("output");
        let slow = format!(
            "{}let slow = [ [ sin(i * 1 deg + j * 1 deg) for i in range(0, 1000) ] for j in range(0, 4000) ]\n",
            two_products("80 mm")
        );
        std::fs::write(&script_path, slow).expect("slow edit");
        std::thread::sleep(Duration::from_millis(600));
        let code = w.interrupt(Duration::from_millis(1500));
        assert_eq!(code, Some(0), "clean exit on Ctrl-C");
        assert_eq!(
            read(&out).expect("output"),
            good,
            "the interrupted rebuild wrote nothing"
        );
        assert!(
            common::temp_files(&dir).is_empty(),
            "{:?}",
            common::temp_files(&dir)
        );
    }
}
