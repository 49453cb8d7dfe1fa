//! Rebuild times of the real `dieface watch`, as a designer sees them.
//!
//! `cargo build --release && cargo run -p dieface-bench --release --bin watch`
//! (`DIEFACE=/path/to/other/dieface` measures another build the same way)
//!
//! Copies the fender example to a temporary folder, starts `target/release/dieface
//! watch fender.die -o fender.glb` on it, and saves edits to the script the way an
//! editor does (write a new file, rename it over the old one). For each kind of edit
//! the script is toggled between two texts at least nine times; each save's time is
//! the one `watch` prints (`rebuilt in 12.3 ms`: from the end of the debounce to the
//! output written). A cold `dieface build` of the same script, timed as a whole
//! process, is the baseline. Prints markdown for BENCHMARKS.md.

use dieface_bench::median;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

/// Saves per kind of edit.
const SAVES: usize = 11;

/// An edit: what it is, and the text before and after.
struct Edit {
    what: &'static str,
    before: &'static str,
    after: &'static str,
}

const EDITS: &[Edit] = &[
    Edit {
        what: "an edit no feature uses (the blank outline's size)",
        before: "1700 mm, 1400 mm, 80 mm",
        after: "1720 mm, 1400 mm, 80 mm",
    },
    Edit {
        what: "a bead edit (the wheel-arch bead's taper)",
        before: "taper = 40 mm",
        after: "taper = 45 mm",
    },
    Edit {
        what: "a binder-wrap edit (one point of the front wrap)",
        before: "(0, -78)",
        after: "(0, -76)",
    },
];

/// The binary under test: `$DIEFACE` (another build, for a before/after), else this
/// checkout's release build.
fn binary() -> PathBuf {
    if let Some(p) = std::env::var_os("DIEFACE") {
        return PathBuf::from(p);
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/release/dieface");
    assert!(
        p.is_file(),
        "build the release binary first: cargo build --release"
    );
    p
}

/// Writes `text` the way editors save: a new file renamed over the old one.
fn save(path: &Path, text: &str) {
    let tmp = path.with_extension("die.swp");
    std::fs::write(&tmp, text).expect("write");
    std::fs::rename(&tmp, path).expect("rename");
}

/// The lines `watch` prints, read on a thread.
fn lines(stdout: ChildStdout) -> Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// The next `built in` / `rebuilt in` line's time in ms (and the line).
fn next_time(rx: &Receiver<String>) -> (f64, String) {
    loop {
        let line = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("watch answers within a minute");
        let Some(rest) = line
            .strip_prefix("rebuilt in ")
            .or_else(|| line.strip_prefix("built in "))
        else {
            continue;
        };
        let ms: f64 = rest
            .split(" ms")
            .next()
            .and_then(|t| t.parse().ok())
            .expect("a time in ms");
        return (ms, line);
    }
}

fn copy_example(to: &Path) -> PathBuf {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/fender");
    std::fs::create_dir_all(to).expect("temp folder");
    for e in std::fs::read_dir(&from).expect("example folder").flatten() {
        if e.path().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).expect("copy");
        }
    }
    to.join("fender.die")
}

struct Watch(Child);

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn main() {
    let bin = binary();
    let dir = std::env::temp_dir().join(format!("dieface-watch-bench-{}", std::process::id()));
    let script = copy_example(&dir);
    let text = std::fs::read_to_string(&script).expect("readable example");
    let out = dir.join("fender.glb");

    // Baseline: whole `dieface build` processes.
    let mut cold = Vec::new();
    for _ in 0..SAVES {
        let t = Instant::now();
        let status = Command::new(&bin)
            .arg("build")
            .arg(&script)
            .arg("-o")
            .arg(&out)
            .stdout(Stdio::null())
            .status()
            .expect("dieface runs");
        assert!(status.success(), "the example builds");
        cold.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let cold = median(&cold);

    let mut child = Command::new(&bin)
        .arg("watch")
        .arg(&script)
        .arg("-o")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("dieface watch starts");
    let rx = lines(child.stdout.take().expect("piped"));
    let _watch = Watch(child);
    let (first, _) = next_time(&rx);

    println!("Fender example, real `dieface watch` (median of {SAVES} saves each; times as `watch` prints them), against a cold `dieface build` process:");
    println!();
    println!("| edit | rebuild (median) | range | cold `dieface build` | ratio cold / rebuild | what re-ran (last save) |");
    println!("| --- | ---: | ---: | ---: | ---: | --- |");
    println!(
        "| first build in `watch` | {first:.1} ms | | {cold:.1} ms | {:.2}x | everything |",
        cold / first
    );
    for edit in EDITS {
        assert!(
            text.contains(edit.before),
            "the example has `{}`",
            edit.before
        );
        let edited = text.replacen(edit.before, edit.after, 1);
        let mut times = Vec::new();
        let mut last = String::new();
        for i in 0..SAVES {
            // Leave the debounce window of the previous save behind.
            std::thread::sleep(Duration::from_millis(300));
            save(&script, if i % 2 == 0 { &edited } else { &text });
            let (ms, line) = next_time(&rx);
            times.push(ms);
            last = line;
        }
        let (lo, hi) = times
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
        let m = median(&times);
        let ran = last.split_once(": ").map_or("", |(_, r)| r);
        println!(
            "| {} | {m:.1} ms | {lo:.1}-{hi:.1} ms | {cold:.1} ms | {:.1}x | {ran} |",
            edit.what,
            cold / m
        );
        // Back to the original text before the next kind of edit.
        if SAVES % 2 == 1 {
            std::thread::sleep(Duration::from_millis(300));
            save(&script, &text);
            next_time(&rx);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
