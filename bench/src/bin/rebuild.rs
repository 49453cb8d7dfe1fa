//! Cold build versus rebuild after a one-declaration edit, for the largest example.
//!
//! `cargo run -p dieface-bench --release --bin rebuild`
//!
//! A cold build evaluates the fender example with a fresh engine, tessellates it and
//! encodes a GLB. A rebuild keeps the engine and the scene cache (as `dieface watch`
//! does), changes one declaration (the draft angle of the key section) and builds again.
//! Both are timed over several repetitions; the median of each and their ratio are
//! printed as a markdown table for BENCHMARKS.md.

use std::path::Path;
use std::time::{Duration, Instant};

use dieface::eval::Engine;
use dieface::export::scene::SceneCache;
use dieface::export::{encode, Format};
use dieface::geom::tessellate::Tolerance;

const REPEATS: usize = 9;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/fender");
    let dir = dir.canonicalize().expect("the fender example exists");
    let text = std::fs::read_to_string(dir.join("fender.die")).expect("readable example");
    let edits = ["let draft = 8 deg", "let draft = 9 deg"];
    assert!(
        text.contains(edits[0]),
        "the example declares the draft angle"
    );
    let tol = Tolerance::new(0.05).expect("valid tolerance");
    if std::env::var_os("PHASES").is_some() {
        parse_cost(&text);
    }

    let build = |engine: &mut Engine, cache: &mut SceneCache, source: &str| -> (Duration, usize) {
        let start = Instant::now();
        let outcome = engine.evaluate("fender.die", source, Some(dir.clone()));
        assert!(outcome.diagnostics.is_empty(), "the example builds");
        let t1 = start.elapsed();
        let scene = cache.build(&outcome, &engine.sources, &tol).expect("scene");
        let t2 = start.elapsed();
        let bytes = encode(&scene, Format::Glb);
        if std::env::var_os("PHASES").is_some() {
            eprintln!(
                "evaluate {:?}, scene {:?}, encode {:?}",
                t1,
                t2 - t1,
                start.elapsed() - t2
            );
        }
        (start.elapsed(), bytes.len())
    };

    let mut cold = Vec::new();
    let mut warm = Vec::new();
    let mut size = 0;
    let mut reran = Vec::new();
    for _ in 0..REPEATS {
        let mut engine = Engine::new(Some(dir.clone()));
        let mut cache = SceneCache::default();
        let (t, n) = build(&mut engine, &mut cache, &text);
        cold.push(t);
        size = n;
        // Edit one declaration and rebuild with the same engine and cache.
        let edited = text.replace(edits[0], edits[1]);
        let (t, _) = build(&mut engine, &mut cache, &edited);
        warm.push(t);
        reran = engine.last_evaluated().to_vec();
    }
    cold.sort();
    warm.sort();
    let (c, w) = (cold[REPEATS / 2], warm[REPEATS / 2]);
    println!("| example | cold build | rebuild after editing `draft` | ratio |");
    println!("| --- | ---: | ---: | ---: |");
    println!(
        "| examples/fender/fender.die ({} KiB GLB at 0.05 mm) | {:.1} ms | {:.2} ms | {:.1}x |",
        size / 1024,
        c.as_secs_f64() * 1e3,
        w.as_secs_f64() * 1e3,
        c.as_secs_f64() / w.as_secs_f64()
    );
    println!();
    println!(
        "Declarations re-evaluated by the rebuild: {}",
        reran.join(", ")
    );
    println!("Medians of {REPEATS} runs each (evaluation + tessellation + GLB encoding, no file writes).");
}

#[allow(dead_code)]
fn parse_cost(text: &str) {
    let start = Instant::now();
    for _ in 0..100 {
        let _ = dieface::syntax::parse(text, dieface::syntax::FileId(0));
    }
    eprintln!("parse: {:?} per file", start.elapsed() / 100);
    let start = Instant::now();
    for _ in 0..100 {
        let _ = dieface::syntax::parse("let a = 1", dieface::syntax::FileId(0));
    }
    eprintln!("parse of one line: {:?}", start.elapsed() / 100);
    for (label, line) in [
        ("let a = 1 mm", "let a = 1 mm\n"),
        ("let b = f(x, y: 2)", "let b = f(x, y: 2)\n"),
        ("tuple", "let c = (1, 2, 3)\n"),
        ("comment", "// a comment line here\n"),
        ("arith", "let d = a * b + c / 2 - (e + f)\n"),
    ] {
        let text: String = (0..70)
            .map(|i| {
                line.replace("let a", &format!("let a{i}"))
                    .replace("let b", &format!("let b{i}"))
                    .replace("let c", &format!("let c{i}"))
                    .replace("let d", &format!("let d{i}"))
            })
            .collect();
        let start = Instant::now();
        for _ in 0..50 {
            let _ = dieface::syntax::parse(&text, dieface::syntax::FileId(0));
        }
        eprintln!("70 x {label}: {:?}", start.elapsed() / 50);
    }
}
