//! Files a script reads and files a build writes, through the real binary: the project
//! root holds for every file opened (imports, `read_obj`; the material library an OBJ
//! names is never opened), a missing `--root` is a usage error, only regular files are
//! read (a FIFO never hangs a command), every read is held to `file_bytes` and an OBJ to
//! `mesh_vertices`; outputs are never a read-only file replaced, and temporary files are
//! named so they cannot collide, removed when their writer was killed, and removed on
//! Ctrl-C.

#[allow(dead_code)] // shares the helpers of other test crates, uses one
mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Longest any command here may take: a hang (a FIFO opened for reading) fails the
/// test instead of blocking it.
const TIMEOUT: Duration = Duration::from_secs(30);

/// A fresh folder for one test under the target's temp dir.
fn temp(name: &str) -> PathBuf {
    common::fresh_dir("cli_files", name)
}

fn write(path: &Path, text: &str) {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).expect("folder");
    }
    std::fs::write(path, text).expect("write");
}

fn start(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_dieface"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run dieface")
}

/// Waits for `child`, killing it (and failing) after [`TIMEOUT`].
fn finish(mut child: Child, what: &str) -> Output {
    let started = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if started.elapsed() > TIMEOUT {
            let _ = child.kill();
            panic!("{what}: dieface hung");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// Runs dieface in `dir` with `--color never`: exit code, stdout, stderr.
fn dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let mut all = args.to_vec();
    all.extend(["--color", "never"]);
    let out = finish(start(dir, &all), &args.join(" "));
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const TRIANGLE: &str = "v 0 0 0\nv 100 0 0\nv 0 100 0\nf 1 2 3\n";

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
}

#[test]
fn an_objs_material_library_is_never_opened() {
    // dieface uses no materials, so the library an `mtllib` line names is not read:
    // not one outside the project, nor a device, nor a named pipe (which would block).
    let dir = temp("mtllib_unread");
    let project = dir.join("project");
    write(&dir.join("outside/secret.mtl"), "newmtl secret\nKd 1 0 0\n");
    write(&project.join("parts/panel.obj"), TRIANGLE);
    #[cfg(unix)]
    mkfifo(&project.join("parts/pipe.mtl"));
    write(
        &project.join("part.die"),
        "let other = 1 mm\nlet mesh = read_obj(\"parts/panel.obj\")\nproduct p = mesh\n",
    );
    for library in [
        "../../outside/secret.mtl",
        "/dev/zero",
        "pipe.mtl",
        "missing.mtl",
    ] {
        write(
            &project.join("parts/panel.obj"),
            &format!("mtllib {library}\n{TRIANGLE}"),
        );
        for command in [
            &["check", "part.die"][..],
            &["inspect", "--json", "part.die"],
            &["build", "part.die", "-o", "p.glb"],
        ] {
            let (code, out, err) = dieface(&project, command);
            assert_eq!(code, Some(0), "{library}, {command:?}: {err}");
            assert!(
                !out.contains("secret") && !err.contains("secret"),
                "{out}{err}"
            );
        }
        assert!(
            project.join("p.glb").exists(),
            "{library}: the product written"
        );
        std::fs::remove_file(project.join("p.glb")).expect("the output removed");
    }
}

#[test]
fn a_root_that_does_not_exist_is_a_usage_error_and_nothing_is_read() {
    let dir = temp("missing_root");
    write(
        &dir.join("part.die"),
        "import \"/etc/passwd\" as p\nlet a = 1 mm\n",
    );
    for command in ["check", "inspect"] {
        let (code, _, err) = dieface(&dir, &[command, "part.die", "--root", "no/such/folder"]);
        assert_eq!(code, Some(2), "{command}: {err}");
        assert!(err.contains("--root `no/such/folder`"), "{err}");
        assert!(!err.contains("root:"), "no line of /etc/passwd: {err}");
    }
    let (code, _, err) = dieface(
        &dir,
        &["build", "part.die", "-o", "p.glb", "--root", "no/such"],
    );
    assert_eq!(code, Some(2), "{err}");

    // A root that does not hold the script is refused too.
    std::fs::create_dir_all(dir.join("elsewhere")).expect("folder");
    let (code, _, err) = dieface(&dir, &["check", "part.die", "--root", "elsewhere"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("outside --root"), "{err}");
}

#[test]
fn only_die_scripts_are_imported_and_never_echoed() {
    let dir = temp("import_not_a_script");
    write(&dir.join("notes.txt"), "SECRET first line\n");
    write(
        &dir.join("part.die"),
        "let a = 1 mm\nimport \"notes.txt\" as notes\nimport \"/etc/passwd\" as p\n",
    );
    let (code, _, err) = dieface(&dir, &["check", "part.die"]);
    assert_eq!(code, Some(1), "{err}");
    assert_eq!(err.matches("die::import_not_a_script").count(), 2, "{err}");
    assert!(err.contains("part.die:2:8"), "at the import's path: {err}");
    assert!(err.contains("part.die:3:8"), "at the import's path: {err}");
    assert!(!err.contains("SECRET") && !err.contains("root:"), "{err}");
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_folder_is_refused_never_waited_on() {
    let dir = temp("fifo");
    mkfifo(&dir.join("module.die"));
    mkfifo(&dir.join("mesh.obj"));
    std::fs::create_dir_all(dir.join("folder.die")).expect("folder");
    write(
        &dir.join("part.die"),
        "import \"module.die\" as m\nimport \"folder.die\" as f\nlet a = read_obj(\"mesh.obj\")\n",
    );
    for command in [
        &["check", "part.die"][..],
        &["inspect", "--json", "part.die"],
    ] {
        let (code, _, err) = dieface(&dir, command);
        assert_eq!(code, Some(1), "{command:?}: {err}");
        assert_eq!(err.matches("die::not_a_file").count(), 3, "{err}");
        for at in ["part.die:1:8", "part.die:2:8", "part.die:3:18"] {
            assert!(err.contains(at), "{at}: {err}");
        }
        assert!(
            err.contains("named pipe") && err.contains("a folder"),
            "{err}"
        );
    }

    // The script itself: a usage error, at once.
    mkfifo(&dir.join("main.die"));
    let (code, _, err) = dieface(&dir, &["check", "main.die"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("named pipe"), "{err}");
}

#[test]
fn every_read_is_held_to_the_file_bytes_limit() {
    let dir = temp("file_bytes");
    write(
        &dir.join("lib.die"),
        &format!("// {}\nlet x = 1 mm\n", "-".repeat(200)),
    );
    write(
        &dir.join("mesh.obj"),
        &format!("# {}\n{TRIANGLE}", "-".repeat(200)),
    );
    write(
        &dir.join("part.die"),
        "import \"lib.die\" as lib\nlet m = read_obj(\"mesh.obj\")\n",
    );
    let limit = ["--limit", "file_bytes=150"];
    let (code, _, err) = dieface(&dir, &[&["check", "part.die"][..], &limit].concat());
    assert_eq!(code, Some(1), "{err}");
    assert_eq!(err.matches("die::limit::file_bytes").count(), 2, "{err}");
    assert!(
        err.contains("part.die:1:8") && err.contains("part.die:2:18"),
        "{err}"
    );
    assert!(
        err.contains("--limit file_bytes=N"),
        "the help says how to raise it: {err}"
    );
    let (code, _, err) = dieface(&dir, &["check", "part.die"]);
    assert_eq!(code, Some(0), "under the default limit: {err}");

    // The script itself: the same diagnostic, at its start, with the same help.
    let (code, _, err) = dieface(&dir, &["check", "lib.die", "--limit", "file_bytes=100"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("die::limit::file_bytes") && err.contains("lib.die:1:1"),
        "{err}"
    );
    assert!(err.contains("--limit file_bytes=N"), "{err}");
}

#[test]
fn an_obj_is_held_to_the_mesh_vertices_limit() {
    let dir = temp("mesh_vertices");
    write(&dir.join("mesh.obj"), TRIANGLE);
    write(&dir.join("part.die"), "let m = read_obj(\"mesh.obj\")\n");
    let (code, _, err) = dieface(&dir, &["check", "part.die", "--limit", "mesh_vertices=2"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("die::limit") && err.contains("3 vertices"),
        "{err}"
    );
    assert!(err.contains("part.die:1:18"), "{err}");
    assert!(err.contains("--limit mesh_vertices=N"), "{err}");
}

const PANEL: &str = r#"let half = 100 mm
let net = [ [ (i * half, j * half, if i == 1 and j == 1 then 30 mm else 0 mm) for j in range(0, 3) ] for i in range(0, 3) ]
product panel = nurbs_surface(degree: (2, 2), points: net)
"#;

#[cfg(unix)]
#[test]
fn a_read_only_output_is_refused_not_replaced() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp("read_only");
    write(&dir.join("part.die"), PANEL);
    write(&dir.join("p.glb"), "protected");
    std::fs::set_permissions(dir.join("p.glb"), std::fs::Permissions::from_mode(0o444))
        .expect("chmod");
    for command in [
        &["build", "part.die", "-o", "p.glb"][..],
        &["watch", "part.die", "-o", "p.glb"],
    ] {
        let (code, _, err) = dieface(&dir, command);
        assert_eq!(code, Some(2), "{command:?}: {err}");
        assert!(
            err.contains("cannot write `p.glb`") && err.contains("read-only"),
            "{err}"
        );
    }
    assert_eq!(
        std::fs::read(dir.join("p.glb")).expect("kept"),
        b"protected"
    );
    assert!(common::temp_files(&dir).is_empty());
}

#[cfg(unix)]
#[test]
fn temporary_files_of_killed_builds_are_removed_and_never_collide() {
    let dir = temp("stale_temps");
    write(&dir.join("part.die"), PANEL);
    // A process that has ended: its id is free.
    let mut gone = Command::new("true").spawn().expect("spawn");
    gone.wait().expect("wait");
    let dead = gone.id();
    let stale = [
        format!(".p.glb.{dead}-0.tmp"),
        format!(".p.glb.{dead}-1f3a.tmp"),
    ];
    for name in &stale {
        write(&dir.join(name), "left by a killed build");
    }
    // Not ours to remove: another output's temporary file, and a file of a live
    // process (this test).
    let kept = [
        format!(".q.glb.{dead}-0.tmp"),
        format!(".p.glb.{}-0.tmp", std::process::id()),
    ];
    for name in &kept {
        write(&dir.join(name), "not stale");
    }
    let (code, _, err) = dieface(&dir, &["build", "part.die", "-o", "p.glb"]);
    assert_eq!(code, Some(0), "{err}");
    let mut left = common::temp_files(&dir);
    left.sort();
    let mut expected = kept.to_vec();
    expected.sort();
    assert_eq!(
        left, expected,
        "the killed builds' files are gone, the others kept"
    );
}

#[cfg(unix)]
#[test]
fn ctrl_c_during_a_build_leaves_no_temporary_file() {
    let dir = temp("interrupted");
    write(&dir.join("part.die"), PANEL);
    // A fine tolerance: tens of megabytes to tessellate and write, so the signal lands
    // during the build (wherever it lands, the invariant below must hold).
    let child = start(
        &dir,
        &[
            "build",
            "part.die",
            "-o",
            "p.glb",
            "--tolerance",
            "0.00005mm",
        ],
    );
    std::thread::sleep(Duration::from_millis(400));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    assert!(status.success());
    let sent = Instant::now();
    let out = finish(child, "interrupted build");
    assert!(
        sent.elapsed() < Duration::from_secs(2),
        "stopped promptly: {:?}",
        sent.elapsed()
    );
    assert!(
        matches!(out.status.code(), Some(130) | Some(0)),
        "{:?}",
        out.status
    );
    assert!(
        common::temp_files(&dir).is_empty(),
        "{:?}",
        common::temp_files(&dir)
    );
    if out.status.code() == Some(130) {
        assert!(
            !dir.join("p.glb").exists(),
            "no output from an interrupted build"
        );
    }
}

#[test]
fn an_output_never_replaces_a_file_the_script_reads() {
    let dir = temp("output_is_input");
    write(&dir.join("mesh.obj"), TRIANGLE);
    write(
        &dir.join("part.die"),
        "product m = read_obj(\"mesh.obj\")\n",
    );
    let (code, _, err) = dieface(&dir, &["build", "part.die", "-o", "./mesh.obj"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("cannot write `./mesh.obj`") && err.contains("the script reads"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("mesh.obj")).expect("kept"),
        TRIANGLE
    );
}

#[test]
fn a_module_that_is_not_utf8_is_refused_with_where() {
    let dir = temp("not_utf8");
    std::fs::write(dir.join("lib.die"), b"let a = 1 mm\nlet caf\xe9 = 2 mm\n").expect("write");
    write(&dir.join("part.die"), "import \"lib.die\" as lib\n");
    let (code, _, err) = dieface(&dir, &["check", "part.die"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("die::not_utf8") && err.contains("part.die:1:8"),
        "{err}"
    );
    assert!(
        err.contains("byte 0xE9 at offset 20 (line 2, column 8)"),
        "{err}"
    );
}
