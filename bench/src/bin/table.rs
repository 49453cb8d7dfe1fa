//! Prints the dieface-vs-curvo comparison as a markdown table (the one in BENCHMARKS.md).
//!
//! `cargo run -p dieface-bench --release --bin table`
//!
//! Each row times both libraries on the same fixtures in the same process: the calls
//! are repeated until one sample takes about `SAMPLE_MS`, samples of the two sides
//! alternate (so drift in clock speed hits both alike), and the median of `SAMPLES`
//! samples is reported. Progress and curvo's tuning go to stderr, the table to stdout.

use std::time::{Duration, Instant};

use dieface_bench::{
    eval_rows, median, tessellation_rows, Fixtures, Row, AGREE, CHORDAL, SAMPLES as PARAMS,
};

const SAMPLE_MS: u64 = 40;
const SAMPLES: usize = 11;

/// Calls per sample so that one sample lasts about `SAMPLE_MS`.
fn calibrate(f: &dyn Fn()) -> usize {
    f(); // warm-up
    let mut reps = 1usize;
    loop {
        let start = Instant::now();
        for _ in 0..reps {
            f();
        }
        let t = start.elapsed();
        if t >= Duration::from_millis(SAMPLE_MS / 4) || reps >= 1 << 24 {
            let per = t.as_secs_f64() / reps as f64;
            return ((SAMPLE_MS as f64 / 1000.0 / per).ceil() as usize).max(1);
        }
        reps *= 4;
    }
}

fn sample(f: &dyn Fn(), reps: usize) -> f64 {
    let start = Instant::now();
    for _ in 0..reps {
        f();
    }
    start.elapsed().as_secs_f64() / reps as f64
}

/// Median time per call of both sides.
fn time_row(row: &Row) -> (f64, f64) {
    let (ra, rb) = (calibrate(&*row.ours), calibrate(&*row.theirs));
    let mut a = Vec::with_capacity(SAMPLES);
    let mut b = Vec::with_capacity(SAMPLES);
    for i in 0..SAMPLES {
        if i % 2 == 0 {
            a.push(sample(&*row.ours, ra));
            b.push(sample(&*row.theirs, rb));
        } else {
            b.push(sample(&*row.theirs, rb));
            a.push(sample(&*row.ours, ra));
        }
    }
    (median(&a), median(&b))
}

fn fmt_time(s: f64) -> String {
    if s < 1e-6 {
        format!("{:.1} ns", s * 1e9)
    } else if s < 1e-3 {
        format!("{:.2} µs", s * 1e6)
    } else {
        format!("{:.2} ms", s * 1e3)
    }
}

fn main() {
    let total = Instant::now();
    eprintln!(
        "building fixtures and checking dieface and curvo agree on {PARAMS} samples each ..."
    );
    let fx = Fixtures::new();
    let tune = std::env::args().any(|a| a == "--tune");
    if tune {
        eprintln!("tessellating, tuning curvo to {CHORDAL} mm (takes several minutes) ...");
    } else {
        eprintln!("tessellating and measuring deviations (recorded curvo settings; --tune searches them again) ...");
    }
    // `--only PREFIX` times only the rows whose id starts with PREFIX (`surface_grid`).
    let only: Option<String> = std::env::args().skip_while(|a| a != "--only").nth(1);
    let mut rows = eval_rows(&fx);
    if only
        .as_deref()
        .is_none_or(|p| "tessellate".starts_with(p) || p.starts_with("tessellate"))
    {
        rows.extend(tessellation_rows(&fx, tune, tune));
    }
    rows.retain(|r| only.as_deref().is_none_or(|p| r.id.starts_with(p)));
    let mut grid_rates = Vec::new();

    let mut lines = Vec::new();
    lines.push("| operation (time per evaluation; per call for tessellation) | dieface | curvo | ratio curvo / dieface |".to_string());
    lines.push("| --- | ---: | ---: | ---: |".to_string());
    let mut meshes = Vec::new();
    let mut slower = Vec::new();
    for row in &rows {
        eprintln!("timing {} ...", row.id);
        let (a, b) = time_row(row);
        let (a, b) = (a / row.ops as f64, b / row.ops as f64);
        let ratio = b / a;
        if row.id.starts_with("surface_grid") {
            grid_rates.push(format!(
                "{}: dieface {:.3e} points/s, curvo {:.3e} points/s (one core)",
                row.label,
                1.0 / a,
                1.0 / b
            ));
        }
        if ratio < 1.0 {
            slower.push(format!("{} ({ratio:.2}x)", row.label));
        }
        lines.push(format!(
            "| {} | {} | {} | {:.2}x |",
            row.label,
            fmt_time(a),
            fmt_time(b),
            ratio
        ));
        if let Some(m) = &row.mesh {
            meshes.push(format!(
                "| {} | {} | {:.4} mm | {} | {:.4} mm | {} |",
                row.label,
                m.ours_triangles,
                m.ours_deviation,
                m.theirs_triangles,
                m.theirs_deviation,
                m.theirs_settings
            ));
        }
    }
    println!("{}", lines.join("\n"));
    println!();
    println!("| tessellation | dieface triangles | dieface max deviation | curvo triangles | curvo max deviation | curvo settings |");
    println!("| --- | ---: | ---: | ---: | ---: | --- |");
    println!("{}", meshes.join("\n"));
    println!();
    println!(
        "Evaluation rows: {PARAMS} fixed random parameters per fixture, both libraries agree on every point and derivative to {AGREE:e} (checked before timing). \
         Times are medians of {SAMPLES} alternating samples of about {SAMPLE_MS} ms each."
    );
    for line in &grid_rates {
        println!("{line}");
    }
    if slower.is_empty() {
        println!("dieface is at least as fast as curvo on every row.");
    } else {
        println!("dieface is slower than curvo on: {}.", slower.join(", "));
    }
    eprintln!("done in {:.1} s", total.elapsed().as_secs_f64());
}
