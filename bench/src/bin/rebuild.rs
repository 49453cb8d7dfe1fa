//! Cold build versus rebuild after a one-declaration edit, for the largest example.
//!
//! `cargo run -p dieface-bench --release --bin rebuild`
//!
//! A cold build evaluates the fender example with a fresh engine, tessellates it and
//! encodes a GLB. A rebuild keeps the engine and the scene cache (as `dieface watch`
//! does), changes one declaration (the size of the blank outline, which no feature uses)
//! and builds again.
//! Both are timed over several repetitions at two tolerances; the medians, their ratio
//! and where the rebuild's time goes are printed as markdown for BENCHMARKS.md.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use dieface::eval::Engine;
use dieface::export::scene::SceneCache;
use dieface::export::{encode, Format};
use dieface::geom::tessellate::Tolerance;

const REPEATS: usize = 9;

/// Time of each phase of one build.
#[derive(Clone, Copy, Default)]
struct Phases {
    evaluate: Duration,
    scene: Duration,
    encode: Duration,
}

impl Phases {
    fn total(&self) -> Duration {
        self.evaluate + self.scene + self.encode
    }
}

fn build(
    engine: &mut Engine,
    cache: &mut SceneCache,
    source: &str,
    dir: &Path,
    tol: &Tolerance,
) -> (Phases, usize) {
    build_file(engine, cache, "fender.die", source, dir, tol)
}

fn build_file(
    engine: &mut Engine,
    cache: &mut SceneCache,
    file: &str,
    source: &str,
    dir: &Path,
    tol: &Tolerance,
) -> (Phases, usize) {
    let start = Instant::now();
    let outcome = engine.evaluate(file, source, Some(dir.to_path_buf()));
    assert!(outcome.diagnostics.is_empty(), "the example builds");
    let evaluated = Instant::now();
    let scene = cache
        .build(&engine.die_model(&outcome), tol)
        .expect("scene");
    let tessellated = Instant::now();
    let bytes = encode(&scene, Format::Glb);
    let done = Instant::now();
    let phases = Phases {
        evaluate: evaluated - start,
        scene: tessellated - evaluated,
        encode: done - tessellated,
    };
    (phases, bytes.len())
}

fn median(mut v: Vec<Phases>) -> Phases {
    v.sort_by_key(Phases::total);
    v[v.len() / 2]
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Times a cold build of `text` and the rebuild after editing it into `edited` (medians
/// of REPEATS), and prints one line: both times, their ratio, where the rebuild's time
/// goes and which declarations re-ran.
fn report_edit(what: &str, text: &str, edited: &str, dir: &Path, chordal: f64) {
    let tol = Tolerance::new(chordal).expect("valid tolerance");
    let (mut cold, mut warm) = (Vec::new(), Vec::new());
    let mut reran = Vec::new();
    for _ in 0..REPEATS {
        let mut engine = Engine::new(Some(dir.to_path_buf()));
        let mut cache = SceneCache::default();
        let (c, _) = build(&mut engine, &mut cache, text, dir, &tol);
        let (w, _) = build(&mut engine, &mut cache, edited, dir, &tol);
        cold.push(c);
        warm.push(w);
        reran = engine.last_evaluated().to_vec();
    }
    let (c, w) = (median(cold), median(warm));
    println!(
        "Editing {what} at {chordal} mm: cold {:.1} ms, rebuild {:.1} ms ({:.1}x; evaluate {:.2} ms, tessellate {:.2} ms, encode {:.2} ms); re-evaluated: {}.",
        ms(c.total()),
        ms(w.total()),
        c.total().as_secs_f64() / w.total().as_secs_f64(),
        ms(w.evaluate),
        ms(w.scene),
        ms(w.encode),
        reran.join(", ")
    );
}

fn main() {
    let dir: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/fender")
        .canonicalize()
        .expect("example");
    let text = std::fs::read_to_string(dir.join("fender.die")).expect("readable example");
    let (before, after) = ("1700 mm, 1400 mm, 80 mm", "1720 mm, 1400 mm, 80 mm");
    assert!(
        text.contains(before),
        "the example declares the blank outline"
    );
    let edited = text.replace(before, after);
    // A designer's edit of a die-face input: one point of the front side's binder wrap,
    // which rebuilds the punch opening and the blankholder.
    let (wrap_before, wrap_after) = ("(0, -78)", "(0, -76)");
    assert!(text.contains(wrap_before), "the example's front wrap");
    let rewrapped = text.replace(wrap_before, wrap_after);

    // Every complete example, cold, at the default tolerance: the "under a second" of
    // issue 7, with each feature's share of the evaluation.
    println!("| example | cold build at 0.05 mm | evaluate | tessellate | encode GLB | slowest declarations |");
    println!("| --- | ---: | ---: | ---: | ---: | --- |");
    for (folder, file) in [("fender", "fender.die"), ("door_outer", "door_outer.die")] {
        let example = dir.join("..").join(folder).canonicalize().expect("example");
        let source = std::fs::read_to_string(example.join(file)).expect("readable example");
        let tol = Tolerance::new(0.05).expect("valid tolerance");
        let mut runs = Vec::new();
        let mut slowest = String::new();
        for _ in 0..REPEATS {
            let mut engine = Engine::new(Some(example.clone()));
            let mut cache = SceneCache::default();
            let (p, _) = build_file(&mut engine, &mut cache, file, &source, &example, &tol);
            runs.push(p);
            let mut times: Vec<(String, Duration)> = engine.last_timings().to_vec();
            times.sort_by(|a, b| b.1.cmp(&a.1));
            slowest = times
                .iter()
                .take(4)
                .map(|(n, d)| format!("{n} {:.0} ms", ms(*d)))
                .collect::<Vec<_>>()
                .join(", ");
        }
        let p = median(runs);
        println!(
            "| {folder} | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms | {slowest} |",
            ms(p.total()),
            ms(p.evaluate),
            ms(p.scene),
            ms(p.encode)
        );
    }
    println!();

    // A bead edit: only that bead re-runs.
    let (bead_before, bead_after) = ("taper = 40 mm", "taper = 45 mm");
    assert!(
        text.contains(bead_before),
        "the example's wheel-arch bead taper"
    );
    let retapered = text.replacen(bead_before, bead_after, 1);
    report_edit("one bead's taper", &text, &retapered, &dir, 0.05);
    for chordal in [0.05, 0.01] {
        report_edit("the front wrap", &text, &rewrapped, &dir, chordal);
    }
    println!();

    println!(
        "| tolerance | GLB size | cold build | rebuild after editing the blank outline | ratio |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: |");
    let mut breakdown = Vec::new();
    let mut reran = Vec::new();
    for chordal in [0.05, 0.01] {
        let tol = Tolerance::new(chordal).expect("valid tolerance");
        let (mut cold, mut warm) = (Vec::new(), Vec::new());
        let mut size = 0;
        for _ in 0..REPEATS {
            let mut engine = Engine::new(Some(dir.clone()));
            let mut cache = SceneCache::default();
            let (c, n) = build(&mut engine, &mut cache, &text, &dir, &tol);
            let (w, _) = build(&mut engine, &mut cache, &edited, &dir, &tol);
            cold.push(c);
            warm.push(w);
            size = n;
            reran = engine.last_evaluated().to_vec();
        }
        let (c, w) = (median(cold), median(warm));
        println!(
            "| {chordal} mm | {} KiB | {:.1} ms | {:.2} ms | {:.1}x |",
            size / 1024,
            ms(c.total()),
            ms(w.total()),
            c.total().as_secs_f64() / w.total().as_secs_f64()
        );
        breakdown.push((chordal, c, w));
    }
    println!();
    println!("| tolerance | build | evaluate (parse included) | tessellate | encode GLB |");
    println!("| ---: | --- | ---: | ---: | ---: |");
    for (chordal, c, w) in breakdown {
        for (label, p) in [("cold", c), ("rebuild", w)] {
            println!(
                "| {chordal} mm | {label} | {:.2} ms | {:.2} ms | {:.2} ms |",
                ms(p.evaluate),
                ms(p.scene),
                ms(p.encode)
            );
        }
    }
    println!();
    println!(
        "Declarations re-evaluated by the rebuild: {}.",
        reran.join(", ")
    );
    println!("Medians of {REPEATS} runs each; no file writes.");
}
