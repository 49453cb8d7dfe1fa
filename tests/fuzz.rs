//! A small seeded fuzzing run, part of the suite: the regression corpus
//! (`tests/fuzz/regressions/`) replayed, then generated and mutated scripts, each run
//! through parse, evaluation, tessellation and every encoder by `dieface-fuzz`'s
//! workers within its time and memory budget. No input may crash, hang or exhaust
//! memory. The long run is `dieface-fuzz run --inputs 1000000` (docs/fuzzing.md).

use std::process::Command;

/// Inputs of the seeded run: about a minute on two cores.
const INPUTS: &str = "1200";

#[test]
fn a_seeded_fuzzing_run_finds_no_crash_hang_or_exhaustion() {
    let found = std::env::temp_dir().join(format!("dieface-fuzz-test-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_dieface-fuzz"))
        .args(["run", "--seed", "7", "--inputs", INPUTS, "--jobs", "2"])
        // Three times the long run's budget: the slowest regressions (kilometre-long
        // openings) take about 6 s of CPU here, and CI's machine may be slower; a hang
        // is still a hang at 30 s.
        .args(["--time-ms", "30000"])
        .arg("--found")
        .arg(&found)
        .output()
        .expect("the fuzzing harness runs");
    let report = String::from_utf8_lossy(&out.stdout);
    eprintln!("{report}{}", String::from_utf8_lossy(&out.stderr));
    // Leave failing inputs for the engineer to read; remove the folder of a clean run.
    assert!(
        out.status.success(),
        "the seeded run found failures (saved in {}):\n{report}",
        found.display()
    );
    assert!(
        report.contains("crashes: 0, over the time budget: 0, over the memory budget: 0"),
        "{report}"
    );
    let _ = std::fs::remove_dir_all(&found);
}
