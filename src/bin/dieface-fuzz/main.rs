//! `dieface-fuzz`: the fuzzing harness, on stable Rust.
//!
//! Random scripts, written from the grammar and the interpreter's own signatures
//! ([`generate`]) and mutated from the examples, the diagnostics corpus, the standard
//! library and the regression corpus ([`mutate`]), are run in-process by worker
//! processes ([`worker`]) through parse, evaluation, tessellation and every encoder,
//! each within a time and a memory budget ([`run`]). An input that panics, kills its
//! worker, or goes over a budget is saved and minimized; it then joins the regression
//! corpus (`tests/fuzz/regressions/`), which every run replays first.
//!
//! ```text
//! dieface-fuzz run --seed 1 --inputs 1000000        # the long run (docs/fuzzing.md)
//! dieface-fuzz run --seed 7 --inputs 2000           # what the test suite runs
//! dieface-fuzz show --seed 1 --index 1234           # one input of a run
//! dieface-fuzz replay found/crash-....die --folder examples/fender
//! ```

mod generate;
mod mutate;
mod rng;
mod run;
mod worker;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::{Args, Parser, Subcommand};

/// The fuzzing harness of dieface.
#[derive(Parser)]
#[command(name = "dieface-fuzz", about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Runs the regression corpus and then random inputs; exit 1 if any failed.
    Run {
        #[command(flatten)]
        budgets: Budgets,
        /// How many random inputs.
        #[arg(long, default_value_t = 10_000)]
        inputs: u64,
        /// Worker processes side by side (default: one per core).
        #[arg(long)]
        jobs: Option<usize>,
        /// Save failing inputs as found, without minimizing them.
        #[arg(long)]
        no_minimize: bool,
        /// Log every input's number, origin, folder, end and time (µs) to this file.
        #[arg(long)]
        log: Option<PathBuf>,
    },
    /// Prints input `index` of the run seeded with `seed`, and the folder it runs in.
    Show {
        #[command(flatten)]
        budgets: Budgets,
        /// The input's number in the run.
        #[arg(long)]
        index: u64,
    },
    /// Runs saved inputs and prints how each ended; exit 1 if any failed.
    Replay {
        #[command(flatten)]
        budgets: Budgets,
        /// The folder of the corpus each input is placed in (for its imports).
        #[arg(long, default_value = "generated")]
        folder: String,
        /// The inputs.
        files: Vec<PathBuf>,
    },
    /// Internal: the worker process the parent starts.
    #[command(hide = true)]
    Worker {
        #[arg(long)]
        scratch: PathBuf,
        #[arg(long)]
        address_space_mb: u64,
    },
}

/// What every command that runs inputs shares.
#[derive(Args)]
struct Budgets {
    /// The run's seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Time budget of one input, milliseconds of the worker's CPU time (a worker idle
    /// for six budgets of wall time is stopped too).
    #[arg(long, default_value_t = 10_000)]
    time_ms: u64,
    /// Memory budget of one input (peak resident), MiB.
    #[arg(long, default_value_t = 2048)]
    memory_mb: u64,
    /// Where failing inputs are saved.
    #[arg(long, default_value = "fuzz-found")]
    found: PathBuf,
    /// The repository whose examples, corpus and standard library seed the inputs.
    #[arg(long, default_value = env!("CARGO_MANIFEST_DIR"))]
    corpus: PathBuf,
}

impl Budgets {
    fn config(&self, inputs: u64, jobs: usize, minimize: bool) -> run::Config {
        run::Config {
            seed: self.seed,
            inputs,
            jobs: jobs.max(1),
            time: Duration::from_millis(self.time_ms),
            memory_mb: self.memory_mb,
            found: self.found.clone(),
            corpus: self.corpus.clone(),
            minimize,
            log: None,
        }
    }
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Run {
            budgets,
            inputs,
            jobs,
            no_minimize,
            log,
        } => {
            let jobs =
                jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
            let mut cfg = budgets.config(inputs, jobs, !no_minimize);
            cfg.log = log;
            let start = Instant::now();
            match run::run(&cfg) {
                Ok(summary) => {
                    print!("{}", summary.report(&cfg, start.elapsed()));
                    if summary.failed() == 0 {
                        ExitCode::SUCCESS
                    } else {
                        println!(
                            "minimized inputs are in {}; add each to {} once fixed",
                            cfg.found.display(),
                            run::REGRESSIONS
                        );
                        ExitCode::from(1)
                    }
                }
                Err(e) => {
                    eprintln!("dieface-fuzz: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::Show { budgets, index } => {
            let (folder, text) = run::show(&budgets.config(0, 1, false), index);
            eprintln!("folder: {folder}");
            print!("{text}");
            ExitCode::SUCCESS
        }
        Command::Replay {
            budgets,
            folder,
            files,
        } => match run::replay(&budgets.config(0, 1, false), &files, &folder) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::from(1),
            Err(e) => {
                eprintln!("dieface-fuzz: {e}");
                ExitCode::from(2)
            }
        },
        Command::Worker {
            scratch,
            address_space_mb,
        } => match worker::serve(&scratch, address_space_mb) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("dieface-fuzz worker: {e}");
                ExitCode::from(2)
            }
        },
    }
}
