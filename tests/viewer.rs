//! The live viewer (`dieface view`, `dieface watch --serve`), on the real binary.
//!
//! In headless Chromium (Debian's `chromium`, driven by playwright-core through
//! `tests/viewer/browser_check.mjs`): the fender's page loads with no console error,
//! its screenshot shows the features' colours, a click on the binder names the piece
//! and its line, the draft and seam analyses draw, a save updates the model in place
//! (the camera stays), and a broken save shows its diagnostic over the model. Over
//! plain HTTP: the served model is the GLB `dieface build` writes, only loopback hosts
//! are answered, a taken port is a usage error, and the embedded three.js is the npm
//! package `package.json` pins.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::picture::Image;

/// A small part whose build takes well under a second ([`common::BUMPED_PANEL`]).
const SMALL: &str = common::BUMPED_PANEL;

/// A running `dieface view`, stopped when dropped.
struct Viewer {
    child: Child,
    port: u16,
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `dieface view SCRIPT --port 0` in `dir` and reads the address it prints.
fn start_view(dir: &Path, script: &str) -> Viewer {
    start_serving(dir, &["view", script, "--port", "0", "--color", "never"])
}

/// Starts `dieface ARGS` (a command that serves the viewer) in `dir` and reads the
/// address it prints.
fn start_serving(dir: &Path, args: &[&str]) -> Viewer {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dieface"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start dieface view");
    let stdout = child.stdout.take().expect("piped stdout");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let first = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("dieface view prints its address");
    let port = first
        .strip_prefix("viewer at http://127.0.0.1:")
        .and_then(|rest| rest.split('/').next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("an address line, not {first:?}"));
    // Keep reading stdout so the server never blocks on a full pipe.
    std::thread::spawn(move || for _ in rx {});
    Viewer { child, port }
}

/// A GET of `path` with the given `Host` header: the status code and the body.
fn get(port: u16, path: &str, host: &str, method: &str) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect to the viewer");
    s.set_read_timeout(Some(Duration::from_secs(60)))
        .expect("timeout");
    write!(s, "{method} {path} HTTP/1.1\r\nHost: {host}\r\n\r\n").expect("send");
    let mut all = Vec::new();
    s.read_to_end(&mut all).expect("read the response");
    let end = all
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a response head");
    let head = String::from_utf8_lossy(&all[..end]).to_string();
    let code = head
        .split(' ')
        .nth(1)
        .and_then(|c| c.parse().ok())
        .expect("a status code");
    (code, all[end + 4..].to_vec())
}

fn get_ok(port: u16, path: &str) -> Vec<u8> {
    let (code, body) = get(port, path, &format!("127.0.0.1:{port}"), "GET");
    assert_eq!(code, 200, "{path}: {}", String::from_utf8_lossy(&body));
    body
}

fn status(port: u16) -> serde_json::Value {
    serde_json::from_slice(&get_ok(port, "/status.json")).expect("status JSON")
}

/// Waits (up to two minutes) until the status satisfies `done`, and returns it.
fn wait_status(port: u16, done: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
    let start = Instant::now();
    loop {
        let s = status(port);
        if done(&s) {
            return s;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "waited for: {s}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn crate_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The hue (degrees) and saturation (0 to 1) of an sRGB pixel.
fn hue_saturation(p: [u8; 3]) -> (f64, f64) {
    let [r, g, b] = p.map(|c| c as f64 / 255.0);
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let d = max - min;
    if d == 0.0 || max == 0.0 {
        return (0.0, 0.0);
    }
    let h = if max == r {
        60.0 * ((g - b) / d).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / d + 2.0)
    } else {
        60.0 * ((r - g) / d + 4.0)
    };
    (h, d / max)
}

/// The share of the picture's pixels in the box `[x0, x1) x [0, height)` whose hue lies
/// within 12 deg of `color`'s and whose saturation is at least half its own: where a
/// shaded surface of that colour is drawn.
fn share_of(img: &Image, x1: usize, color: [u8; 3]) -> f64 {
    let (hue, sat) = hue_saturation(color);
    let mut n = 0;
    let mut all = 0;
    for y in 0..img.height {
        for x in 0..x1.min(img.width) {
            all += 1;
            let (h, s) = hue_saturation(img.at(x, y));
            let dh = (h - hue).abs();
            if dh.min(360.0 - dh) < 12.0 && s >= 0.5 * sat {
                n += 1;
            }
        }
    }
    n as f64 / all as f64
}

/// The share of the pixels left of `x1` whose hue lies in `hues` (degrees) with a
/// saturation of at least 0.3.
fn share_in_hues(img: &Image, x1: usize, hues: std::ops::Range<f64>) -> f64 {
    let width = x1.min(img.width);
    let n = (0..img.height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (h, s) = hue_saturation(img.at(x, y));
            hues.contains(&h) && s >= 0.3
        })
        .count();
    n as f64 / (width * img.height) as f64
}

/// `rgb(1, 2, 3)` as bytes.
fn css_rgb(text: &str) -> [u8; 3] {
    let inner = text
        .trim_start_matches("rgb(")
        .trim_end_matches(')')
        .split(',')
        .map(|c| c.trim().parse::<u8>().expect("a channel"))
        .collect::<Vec<_>>();
    [inner[0], inner[1], inner[2]]
}

#[test]
fn the_fender_in_headless_chromium() {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    assert!(
        Path::new(&chromium).exists(),
        "no Chromium at {chromium}: the README's test command (scripts/test) installs Debian's `chromium`"
    );
    let dir = common::fresh_dir("viewer", "browser");
    let script_text =
        std::fs::read_to_string(crate_root().join("examples/fender/fender.die")).expect("fender");
    std::fs::write(dir.join("fender.die"), &script_text).expect("copy the fender");
    let viewer = start_view(&dir, "fender.die");

    let out = Command::new("node")
        .arg(crate_root().join("tests/viewer/browser_check.mjs"))
        .arg(format!("http://127.0.0.1:{}/", viewer.port))
        .arg(dir.join("fender.die"))
        .arg(&dir)
        .current_dir(crate_root())
        .output()
        .expect("run node (the README's test command installs playwright-core)");
    assert!(
        out.status.success(),
        "browser check failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).expect("the check's JSON");
    eprintln!(
        "viewer: save to model drawn {} ms (status heard at {} ms, build {} ms; page {})",
        r["saveToModelMs"], r["saveToStatusMs"], r["buildMs"], r["pageTimings"]
    );

    // No console error from loading, picking, both analyses, a save and a broken save.
    assert_eq!(r["consoleErrors"], serde_json::json!([]), "{r}");
    assert_eq!(r["title"], "fender.die");

    // The model is drawn, each of the die face's features in its legend colour.
    let canvas_width = r["canvas"]["width"].as_f64().expect("canvas width") as usize;
    let model = Image::read(&dir.join("model.png"));
    let background = [238, 241, 245];
    let drawn = (0..model.height)
        .flat_map(|y| (0..canvas_width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = model.at(x, y);
            (0..3).any(|i| p[i].abs_diff(background[i]) > 12)
        })
        .count();
    let drawn_share = drawn as f64 / (canvas_width * model.height) as f64;
    assert!(
        drawn_share > 0.1,
        "the model covers {drawn_share:.3} of the view"
    );
    let legend = r["legend"].as_array().expect("legend rows");
    for kind in ["product", "blankholder", "step_draw", "bead"] {
        let row = legend
            .iter()
            .find(|row| row["kind"] == kind)
            .unwrap_or_else(|| panic!("{kind} in the legend: {legend:?}"));
        let color = css_rgb(row["color"].as_str().expect("a CSS colour"));
        let share = share_of(&model, canvas_width, color);
        let least = if kind == "bead" { 0.001 } else { 0.02 };
        assert!(
            share > least,
            "{kind} {color:?} covers {share:.4} of the view"
        );
    }

    // A click on a binder piece names it, its kind and the line that declared it.
    let binder_line = script_text
        .lines()
        .position(|l| l.starts_with("blankholder binder"))
        .expect("the binder's line")
        + 1;
    let pick = &r["click"]["pick"];
    let picked = pick["name"].as_str().expect("a picked name");
    assert!(picked.starts_with("binder/"), "{pick}");
    assert_eq!(pick["kind"], "blankholder");
    assert_eq!(pick["line"], binder_line);
    let panel = r["click"]["panel"].as_str().expect("the pick panel");
    assert!(
        panel.contains(&format!("fender.die:{binder_line}")),
        "{panel}"
    );
    assert!(
        panel.contains("area") && panel.contains("worst:"),
        "{panel}"
    );

    // Draft analysis: the binder and product flat or drafted past 8 deg, green, where
    // the features' colours were; the step draw's walls (8 deg designed, 7.8 deg at
    // the least, inspect says) green and amber.
    let draft = Image::read(&dir.join("draft.png"));
    let green = share_in_hues(&draft, canvas_width, 80.0..140.0);
    assert!(green > 0.1, "green covers {green:.3}");
    let binder_green = share_of(&draft, canvas_width, [137, 211, 149]);
    assert!(binder_green < 0.01, "binder colour left: {binder_green:.4}");
    assert!(r["draftLegend"]
        .as_str()
        .is_some_and(|t| t.contains("8°") && t.contains("5")));
    // Seam analysis: the fender's patches meet tangentially (inspect says normal_angle 0
    // at every seam), so the largest jump is well under the 0.5 deg G1 tolerance.
    let seams = &r["seams"];
    assert!(seams["count"].as_u64().is_some_and(|n| n > 1000), "{seams}");
    assert!(
        seams["max_deg"].as_f64().is_some_and(|d| d < 0.5),
        "{seams}"
    );
    // Switching the binder off hides its seams (with the step draw and between its
    // own patches), and on again shows them all.
    let drawn = seams["drawn"].as_u64().expect("points drawn");
    assert_eq!(Some(drawn), seams["count"].as_u64(), "{seams}");
    let without = seams["drawnWithoutBinder"].as_u64().expect("points drawn");
    assert!(without > 0 && without < drawn, "{seams}");
    assert_eq!(seams["drawnAgain"].as_u64(), Some(drawn), "{seams}");

    // A save moves the bead: a new model, drawn within 2 s of the save (the issue's
    // figure; its time is measured in bench/viewer-latency.mjs), with the camera where
    // it was.
    assert!(
        r["afterSave"]["version"].as_u64() > r["loadedVersion"].as_u64(),
        "{r}"
    );
    let latency = r["saveToModelMs"].as_f64().expect("save to model drawn");
    assert!(
        latency > 0.0 && latency < 2000.0,
        "save to model drawn: {latency} ms"
    );
    assert_eq!(r["cameraKept"], true);
    // A broken save: its diagnostic shown, the model kept; fixed again, it goes.
    let diagnostic = r["diagnostic"].as_str().expect("the diagnostic");
    assert!(
        diagnostic.contains("cannot add a length and an angle") && diagnostic.contains("broken"),
        "{diagnostic}"
    );
    assert_eq!(r["afterBroken"]["state"], "error");
    assert_eq!(r["modelKept"], true);
    assert_eq!(r["recovered"], true);
    // Without WebGL the page says why it draws nothing, and what draws without it.
    let without = r["withoutWebgl"].as_str().expect("the page's message");
    assert!(
        without.contains("cannot draw the model") && without.contains("dieface render"),
        "{without}"
    );
    drop(viewer);
}

#[test]
fn the_served_model_is_the_built_glb_and_a_broken_save_keeps_it() {
    let dir = common::fresh_dir("viewer", "http");
    std::fs::write(dir.join("part.die"), SMALL).expect("write script");
    let (code, _, stderr) = common::run_dieface(&dir, &["build", "part.die", "-o", "part.glb"]);
    assert_eq!(code, Some(0), "{stderr}");
    let built = std::fs::read(dir.join("part.glb")).expect("the built GLB");

    let viewer = start_view(&dir, "part.die");
    let port = viewer.port;
    let first = wait_status(port, |s| s["state"] == "ok");
    assert!(first["model_version"].as_u64() > Some(0));
    assert_eq!(get_ok(port, "/model.glb"), built, "the GLB `build` writes");

    let page = String::from_utf8(get_ok(port, "/")).expect("UTF-8 page");
    assert!(page.contains("importmap") && page.contains("/viewer.js"));
    let licence = String::from_utf8(get_ok(port, "/vendor/three/LICENSE")).expect("text");
    assert!(licence.contains("MIT License"));
    let info: serde_json::Value =
        serde_json::from_slice(&get_ok(port, "/info.json")).expect("JSON");
    let panel = info["declarations"]
        .as_array()
        .and_then(|d| d.iter().find(|d| d["name"] == "panel"))
        .expect("the product in info.json");
    assert_eq!(panel["kind"], "product");
    assert_eq!(panel["line"], 5);
    let piece: serde_json::Value =
        serde_json::from_slice(&get_ok(port, "/piece.json?name=panel")).expect("JSON");
    assert!(
        piece["summary"]
            .as_str()
            .is_some_and(|s| s.starts_with("surface 2x2")),
        "{piece}"
    );
    let seams: serde_json::Value =
        serde_json::from_slice(&get_ok(port, "/seams.json")).expect("JSON");
    assert_eq!(seams["count"], 0, "one surface has no seam");

    // Refusals: another host (DNS rebinding), an unknown path or piece, a POST.
    let (code, _) = get(port, "/", "attacker.example:80", "GET");
    assert_eq!(code, 403);
    let (code, _) = get(port, "/nothing", &format!("localhost:{port}"), "GET");
    assert_eq!(code, 404);
    let (code, _) = get(
        port,
        "/piece.json?name=nope",
        &format!("localhost:{port}"),
        "GET",
    );
    assert_eq!(code, 404);
    let (code, _) = get(port, "/", &format!("localhost:{port}"), "POST");
    assert_eq!(code, 405);

    // A broken save: the status says error with the diagnostic; the model stays.
    let before = status(port)["version"].as_u64().expect("version");
    std::fs::write(
        dir.join("part.die"),
        format!("{SMALL}\nlet broken = 1 mm + 2 deg\n"),
    )
    .expect("write");
    let failed = wait_status(port, |s| {
        s["state"] == "error" && s["version"].as_u64() > Some(before)
    });
    let text = failed["error"].as_str().expect("the diagnostic text");
    assert!(
        text.contains("cannot add a length and an angle") && text.contains("part.die:"),
        "{text}"
    );
    assert!(
        !text.contains('\u{1b}'),
        "no terminal colour codes in the page's text"
    );
    assert_eq!(failed["model_version"], first["model_version"]);
    assert_eq!(
        get_ok(port, "/model.glb"),
        built,
        "the last good model is still served"
    );

    // Fixed with a changed model: a new model version, different bytes.
    std::fs::write(dir.join("part.die"), SMALL.replace("30 mm", "40 mm")).expect("write");
    let fixed = wait_status(port, |s| {
        s["state"] == "ok" && s["model_version"].as_u64() > first["model_version"].as_u64()
    });
    assert!(fixed["took_ms"].as_f64().is_some());
    assert_ne!(get_ok(port, "/model.glb"), built);
    drop(viewer);
}

#[test]
fn watch_serve_writes_its_outputs_and_serves_the_same_model() {
    let dir = common::fresh_dir("viewer", "watch");
    std::fs::write(dir.join("part.die"), SMALL).expect("write script");
    let viewer = start_serving(
        &dir,
        &[
            "watch", "part.die", "-o", "part.glb", "--serve", "--port", "0",
        ],
    );
    wait_status(viewer.port, |s| s["state"] == "ok");
    let written = std::fs::read(dir.join("part.glb")).expect("watch wrote its output");
    assert_eq!(get_ok(viewer.port, "/model.glb"), written);
}

#[test]
fn a_taken_port_is_a_usage_error_that_says_how_to_choose_another() {
    let dir = common::fresh_dir("viewer", "port");
    std::fs::write(dir.join("part.die"), SMALL).expect("write script");
    let taken = TcpListener::bind(("127.0.0.1", 0)).expect("a free port");
    let port = taken.local_addr().expect("address").port().to_string();
    let (code, _, stderr) = common::run_dieface(&dir, &["view", "part.die", "--port", &port]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains(&format!("port {port} on 127.0.0.1 is taken")),
        "{stderr}"
    );
    assert!(stderr.contains("--port 0"), "{stderr}");
}

#[test]
fn the_embedded_three_is_the_pinned_npm_package() {
    let root = crate_root();
    let package: serde_json::Value =
        serde_json::from_slice(&std::fs::read(root.join("package.json")).expect("package.json"))
            .expect("JSON");
    let pinned = package["devDependencies"]["three"]
        .as_str()
        .expect("three pinned");
    let vendored = root.join("src/cli/viewer/vendor/three");
    let version = std::fs::read_to_string(vendored.join("VERSION")).expect("VERSION");
    assert_eq!(
        version.trim(),
        pinned,
        "run scripts/vendor-three after changing the pin"
    );
    let installed = root.join("node_modules/three");
    assert!(
        installed.is_dir(),
        "node_modules/three missing: the README's test command runs `npm ci`"
    );
    let mut files = Vec::new();
    let mut stack = vec![vendored.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d)
            .expect("read dir")
            .map(|e| e.expect("entry").path())
        {
            if e.is_dir() {
                stack.push(e);
            } else if e.file_name().is_some_and(|n| n != "VERSION") {
                files.push(e);
            }
        }
    }
    assert!(files.len() >= 7, "{files:?}");
    for f in files {
        let rel = f.strip_prefix(&vendored).expect("inside");
        let theirs = std::fs::read(installed.join(rel)).expect("the npm file");
        assert!(
            std::fs::read(&f).expect("ours") == theirs,
            "{} differs from three {pinned} on npm",
            rel.display()
        );
    }
}
