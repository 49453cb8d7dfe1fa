//! The parent of a fuzzing run: makes the inputs, hands them to worker processes, holds
//! each to its time and memory budget, saves and minimizes every input that fails, and
//! sums the run up.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::generate::{self, Signatures};
use crate::mutate;
use crate::rng::Rng;
use crate::worker::write_frame;

/// The budgets and sizes of a run.
#[derive(Clone)]
pub struct Config {
    /// The run's seed: input `i` of seed `s` is the same on every machine.
    pub seed: u64,
    /// How many random inputs (the regression corpus runs first, besides these).
    pub inputs: u64,
    /// Worker processes side by side.
    pub jobs: usize,
    /// Time budget of one input.
    pub time: Duration,
    /// Memory budget of one input (peak resident), MiB.
    pub memory_mb: u64,
    /// Where failing inputs are saved.
    pub found: PathBuf,
    /// The repository, whose examples, corpus and standard library are the seeds.
    pub corpus: PathBuf,
    /// Whether failing inputs are minimized.
    pub minimize: bool,
    /// A file to log every input's number, origin, folder, end and time to.
    pub log: Option<PathBuf>,
}

/// The folders whose `.die` files seed the mutations (relative to the repository); the
/// workers get a copy of each, so imports and OBJ reads resolve.
const SEED_FOLDERS: &[&str] = &[
    "examples",
    "tests/diagnostics",
    "stdlib",
    "tests/fuzz/regressions",
];

/// The folder of the regression corpus: every failure found joins it.
pub const REGRESSIONS: &str = "tests/fuzz/regressions";

/// A script to mutate, with the folder it lives in.
struct Seed {
    folder: String,
    text: String,
}

/// Every seed script of the repository.
fn load_seeds(corpus: &Path) -> Vec<Seed> {
    let mut seeds = Vec::new();
    for folder in SEED_FOLDERS {
        let mut stack = vec![corpus.join(folder)];
        while let Some(dir) = stack.pop() {
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
            paths.sort();
            for p in paths {
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|e| e == "die") {
                    if let Ok(text) = std::fs::read_to_string(&p) {
                        let folder = p
                            .parent()
                            .and_then(|d| d.strip_prefix(corpus).ok())
                            .map(|d| d.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        seeds.push(Seed { folder, text });
                    }
                }
            }
        }
    }
    seeds
}

/// Where an input came from.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Origin {
    Regression,
    Generated,
    Mutated,
}

/// Input `index` of the run: its folder, text and origin.
fn make_input(
    cfg: &Config,
    seeds: &[Seed],
    sig: &Signatures,
    index: u64,
) -> (String, String, Origin) {
    let mut rng = Rng::for_input(cfg.seed, index);
    if seeds.is_empty() || rng.chance(0.4) {
        return (
            "generated".into(),
            generate::script(&mut rng, sig),
            Origin::Generated,
        );
    }
    let seed = &seeds[rng.below(seeds.len())];
    let donors: Vec<String> = (0..3)
        .map(|_| seeds[rng.below(seeds.len())].text.clone())
        .collect();
    (
        seed.folder.clone(),
        mutate::mutate(&mut rng, &seed.text, &donors),
        Origin::Mutated,
    )
}

/// How an input ended, as the parent sees it.
#[derive(Debug)]
enum Verdict {
    /// Finished: clean or with diagnostics; time and peak memory.
    Done {
        clean: bool,
        micros: u64,
        peak_kib: u64,
    },
    /// A panic caught in the worker.
    Panic(String),
    /// The worker died (abort, stack overflow, a signal, out of address space).
    Died(String),
    /// Over the time budget: the worker was killed.
    Hang,
}

/// How often the parent looks at a busy worker's CPU time.
const POLL: Duration = Duration::from_millis(100);

/// Wall time, in time budgets, after which a worker is stopped even if it is idle.
const WALL_FACTOR: u32 = 6;

/// The CPU time (user and system, all threads) process `pid` has used, from
/// `/proc/PID/stat` (zero where it cannot be read: the wall-time bound still holds).
fn cpu_time(pid: u32) -> Duration {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return Duration::ZERO;
    };
    // Fields after the command name (which may hold spaces), closed by its `)`.
    let Some(rest) = stat.rfind(')').map(|i| &stat[i + 1..]) else {
        return Duration::ZERO;
    };
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the whole line, 12 and 13 here.
    let ticks: u64 = [11, 12]
        .iter()
        .filter_map(|&i| fields.get(i).and_then(|f| f.parse::<u64>().ok()))
        .sum();
    // SAFETY: sysconf only reads a system constant.
    let per_second = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as u64;
    Duration::from_millis(ticks * 1000 / per_second)
}

/// A failure kind, for the summary and file names.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
pub enum Failure {
    Crash,
    Hang,
    Memory,
}

impl Failure {
    fn word(self) -> &'static str {
        match self {
            Failure::Crash => "crash",
            Failure::Hang => "hang",
            Failure::Memory => "memory",
        }
    }
}

/// The failure a verdict is, if any, under `cfg`'s budgets.
fn failure(v: &Verdict, cfg: &Config) -> Option<(Failure, String)> {
    match v {
        Verdict::Done { peak_kib, .. } if *peak_kib > cfg.memory_mb * 1024 => Some((
            Failure::Memory,
            format!("peak {} MiB over {} MiB", peak_kib / 1024, cfg.memory_mb),
        )),
        Verdict::Done { .. } => None,
        Verdict::Panic(m) => Some((Failure::Crash, format!("panic: {m}"))),
        Verdict::Died(m) if m.contains("memory allocation of") => {
            Some((Failure::Memory, format!("out of address space: {m}")))
        }
        Verdict::Died(m) => Some((Failure::Crash, format!("died: {m}"))),
        Verdict::Hang => Some((
            Failure::Hang,
            format!(
                "over the time budget of {} ms of CPU time",
                cfg.time.as_millis()
            ),
        )),
    }
}

/// A worker process and its pipes.
struct Worker {
    child: Child,
    stdin: ChildStdin,
    replies: Receiver<String>,
    stderr: Arc<Mutex<String>>,
    scratch: PathBuf,
}

impl Worker {
    /// Starts a worker with its own scratch copy of the seed folders.
    fn start(cfg: &Config, scratch: &Path) -> std::io::Result<Worker> {
        if !scratch.exists() {
            for folder in SEED_FOLDERS {
                copy_tree(&cfg.corpus.join(folder), &scratch.join(folder))?;
            }
        }
        let exe = std::env::current_exe()?;
        // Address space: the memory budget, the worker's thread stacks (reserved, not
        // used) and room for the allocator's arenas.
        let address_space = cfg.memory_mb * 2 + 4096;
        let mut child = Command::new(exe)
            .arg("worker")
            .arg("--scratch")
            .arg(scratch)
            .arg("--address-space-mb")
            .arg(address_space.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        let stdin = child
            .stdin
            .take()
            .ok_or_else(|| std::io::Error::other("no stdin"))?;
        let stdout = child
            .stdout
            .take()
            .ok_or_else(|| std::io::Error::other("no stdout"))?;
        let mut stderr_pipe = child
            .stderr
            .take()
            .ok_or_else(|| std::io::Error::other("no stderr"))?;
        let (tx, replies) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let stderr = Arc::new(Mutex::new(String::new()));
        let tail = stderr.clone();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = stderr_pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                if let Ok(mut t) = tail.lock() {
                    t.push_str(&String::from_utf8_lossy(&buf[..n]));
                    if t.len() > 8192 {
                        let cut = t.len() - 4096;
                        let cut = (cut..t.len()).find(|&i| t.is_char_boundary(i)).unwrap_or(0);
                        t.drain(..cut);
                    }
                }
            }
        });
        Ok(Worker {
            child,
            stdin,
            replies,
            stderr,
            scratch: scratch.to_path_buf(),
        })
    }

    /// Runs one input; a worker that hung or died is replaced.
    fn run(&mut self, cfg: &Config, folder: &str, text: &str) -> Verdict {
        let sent = write_frame(&mut self.stdin, folder.as_bytes())
            .and_then(|_| write_frame(&mut self.stdin, text.as_bytes()))
            .and_then(|_| self.stdin.flush());
        let verdict = match sent {
            Err(_) => self.died(),
            Ok(()) => self.wait_for_reply(cfg),
        };
        if matches!(verdict, Verdict::Hang | Verdict::Died(_)) {
            if let Ok(w) = Worker::start(cfg, &self.scratch) {
                *self = w;
            }
        }
        verdict
    }

    /// Waits for the worker's reply within the time budget, counted in the worker's CPU
    /// time (all its threads), so a busy machine does not make a slow input a hang; a
    /// worker that waits without working (on a pipe, say) is stopped after
    /// [`WALL_FACTOR`] times the budget of wall time.
    fn wait_for_reply(&mut self, cfg: &Config) -> Verdict {
        let pid = self.child.id();
        let cpu_at_start = cpu_time(pid);
        let started = Instant::now();
        loop {
            match self.replies.recv_timeout(POLL) {
                Ok(line) => return parse_reply(&line),
                Err(RecvTimeoutError::Disconnected) => return self.died(),
                Err(RecvTimeoutError::Timeout) => {
                    let cpu = cpu_time(pid).saturating_sub(cpu_at_start);
                    if cpu > cfg.time || started.elapsed() > cfg.time * WALL_FACTOR {
                        let _ = self.child.kill();
                        let _ = self.child.wait();
                        return Verdict::Hang;
                    }
                }
            }
        }
    }

    fn died(&mut self) -> Verdict {
        // A worker that cannot be written to may still be alive, waiting on its input:
        // it is stopped, or waiting for it would wait for ever.
        let _ = self.child.kill();
        let status = self.child.wait().map(|s| s.to_string()).unwrap_or_default();
        // Let the stderr reader catch the last words.
        std::thread::sleep(Duration::from_millis(50));
        let tail = self.stderr.lock().map(|t| t.clone()).unwrap_or_default();
        let last: Vec<&str> = tail.lines().filter(|l| !l.trim().is_empty()).collect();
        let words = last[last.len().saturating_sub(3)..].join(" | ");
        Verdict::Died(format!("{status}: {words}"))
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn parse_reply(line: &str) -> Verdict {
    let mut parts = line.splitn(5, ' ');
    let (_, class, micros, kib) = (parts.next(), parts.next(), parts.next(), parts.next());
    let micros = micros.and_then(|m| m.parse().ok()).unwrap_or(0);
    let peak_kib = kib.and_then(|m| m.parse().ok()).unwrap_or(0);
    match class {
        Some("panic") => Verdict::Panic(parts.next().unwrap_or("").to_string()),
        Some(c) => Verdict::Done {
            clean: c == "clean",
            micros,
            peak_kib,
        },
        None => Verdict::Died(format!("unreadable reply `{line}`")),
    }
}

/// Copies a folder tree (regular files only).
fn copy_tree(from: &Path, to: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(to)?;
    let Ok(entries) = std::fs::read_dir(from) else {
        return Ok(());
    };
    for e in entries.flatten() {
        let p = e.path();
        let ty = e.file_type()?;
        if ty.is_dir() {
            copy_tree(&p, &to.join(e.file_name()))?;
        } else if ty.is_file() {
            std::fs::copy(&p, to.join(e.file_name()))?;
        }
    }
    Ok(())
}

/// What a run found, summed up.
#[derive(Default)]
pub struct Summary {
    by_origin: BTreeMap<Origin, u64>,
    clean: u64,
    problems: u64,
    failures: BTreeMap<Failure, Vec<PathBuf>>,
    slowest_ms: f64,
    largest_kib: u64,
    total_micros: u64,
    /// Inputs that took under 1 ms, 10 ms, 100 ms, 1 s, and longer.
    times: [u64; 5],
}

impl Summary {
    /// Inputs that failed.
    pub fn failed(&self) -> usize {
        self.failures.values().map(Vec::len).sum()
    }

    fn count(&self, f: Failure) -> usize {
        self.failures.get(&f).map_or(0, Vec::len)
    }

    /// The run in a few lines, for the terminal and the issue note.
    pub fn report(&self, cfg: &Config, elapsed: Duration) -> String {
        let total: u64 = self.by_origin.values().sum();
        let mut s = format!(
            "dieface-fuzz: seed {}, {} inputs ({} regression, {} generated, {} mutated) in {:.1} s on {} workers ({:.0} inputs/s)\n",
            cfg.seed,
            total,
            self.by_origin.get(&Origin::Regression).unwrap_or(&0),
            self.by_origin.get(&Origin::Generated).unwrap_or(&0),
            self.by_origin.get(&Origin::Mutated).unwrap_or(&0),
            elapsed.as_secs_f64(),
            cfg.jobs,
            total as f64 / elapsed.as_secs_f64().max(1e-9),
        );
        s += &format!(
            "  ended clean: {}, with diagnostics: {}; mean {:.2} ms, slowest {:.0} ms (budget {} ms), largest peak {} MiB (budget {} MiB)\n",
            self.clean,
            self.problems,
            self.total_micros as f64 / 1000.0 / total.max(1) as f64,
            self.slowest_ms,
            cfg.time.as_millis(),
            self.largest_kib / 1024,
            cfg.memory_mb,
        );
        s += &format!(
            "  times: {} under 1 ms, {} under 10 ms, {} under 100 ms, {} under 1 s, {} longer\n",
            self.times[0], self.times[1], self.times[2], self.times[3], self.times[4]
        );
        s += &format!(
            "  crashes: {}, over the time budget: {}, over the memory budget: {}\n",
            self.count(Failure::Crash),
            self.count(Failure::Hang),
            self.count(Failure::Memory)
        );
        for (f, paths) in &self.failures {
            for p in paths {
                s += &format!("  {}: {}\n", f.word(), p.display());
            }
        }
        s
    }
}

/// Runs the regression corpus, then `cfg.inputs` random inputs, on `cfg.jobs` workers.
pub fn run(cfg: &Config) -> std::io::Result<Summary> {
    let seeds = Arc::new(load_seeds(&cfg.corpus));
    let sig = Arc::new(Signatures::standard());
    let regressions: Arc<Vec<Seed>> = Arc::new(
        load_seeds(&cfg.corpus)
            .into_iter()
            .filter(|s| s.folder.starts_with(REGRESSIONS))
            .collect(),
    );
    let next = Arc::new(AtomicU64::new(0));
    let summary = Arc::new(Mutex::new(Summary::default()));
    let log = match &cfg.log {
        Some(p) => Some(Arc::new(Mutex::new(std::fs::File::create(p)?))),
        None => None,
    };
    let started = Instant::now();
    let total = regressions.len() as u64 + cfg.inputs;
    let mut threads = Vec::new();
    for job in 0..cfg.jobs {
        let (cfg, seeds, sig, regressions, next, summary) = (
            cfg.clone(),
            seeds.clone(),
            sig.clone(),
            regressions.clone(),
            next.clone(),
            summary.clone(),
        );
        let log = log.clone();
        threads.push(std::thread::spawn(move || -> std::io::Result<()> {
            let scratch =
                std::env::temp_dir().join(format!("dieface-fuzz-{}-{job}", std::process::id()));
            let _ = std::fs::remove_dir_all(&scratch);
            let mut worker = Worker::start(&cfg, &scratch)?;
            loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= total {
                    break;
                }
                let (folder, text, origin) = match regressions.get(i as usize) {
                    Some(r) => (r.folder.clone(), r.text.clone(), Origin::Regression),
                    None => make_input(&cfg, &seeds, &sig, i - regressions.len() as u64),
                };
                let verdict = worker.run(&cfg, &folder, &text);
                let failed = failure(&verdict, &cfg);
                if let Some(log) = &log {
                    if let Ok(mut f) = log.lock() {
                        let (end, micros) = match &verdict {
                            Verdict::Done { clean, micros, .. } => {
                                (if *clean { "clean" } else { "problems" }, *micros)
                            }
                            Verdict::Panic(_) => ("panic", 0),
                            Verdict::Died(_) => ("died", 0),
                            Verdict::Hang => ("hang", 0),
                        };
                        writeln!(f, "{i} {origin:?} {folder} {end} {micros}")?;
                    }
                }
                let saved = match &failed {
                    Some((kind, why)) => Some(save_failure(
                        &cfg,
                        &mut worker,
                        *kind,
                        why,
                        &folder,
                        &text,
                        origin,
                        i,
                    )?),
                    None => None,
                };
                let mut s = summary
                    .lock()
                    .map_err(|_| std::io::Error::other("poisoned"))?;
                *s.by_origin.entry(origin).or_default() += 1;
                if let Verdict::Done {
                    clean,
                    micros,
                    peak_kib,
                } = verdict
                {
                    if clean {
                        s.clean += 1;
                    } else {
                        s.problems += 1;
                    }
                    s.slowest_ms = s.slowest_ms.max(micros as f64 / 1000.0);
                    s.largest_kib = s.largest_kib.max(peak_kib);
                    s.total_micros += micros;
                    let bucket = [1_000, 10_000, 100_000, 1_000_000]
                        .iter()
                        .position(|&limit| micros < limit)
                        .unwrap_or(4);
                    s.times[bucket] += 1;
                }
                if let (Some((kind, _)), Some(path)) = (failed, saved) {
                    s.failures.entry(kind).or_default().push(path);
                }
                let done: u64 = s.by_origin.values().sum();
                if done % 10_000 == 0 {
                    eprintln!(
                        "dieface-fuzz: {done} of {total} inputs, {} failed, {:.0} s",
                        s.failed(),
                        started.elapsed().as_secs_f64()
                    );
                }
            }
            drop(worker);
            let _ = std::fs::remove_dir_all(&scratch);
            Ok(())
        }));
    }
    for t in threads {
        t.join()
            .map_err(|_| std::io::Error::other("a fuzzing thread panicked"))??;
    }
    let summary = Arc::try_unwrap(summary)
        .map_err(|_| std::io::Error::other("threads still hold the summary"))?
        .into_inner()
        .map_err(|_| std::io::Error::other("poisoned"))?;
    Ok(summary)
}

/// Saves a failing input (minimized, when asked) with a note of how it failed, and
/// returns its path.
#[allow(clippy::too_many_arguments)]
fn save_failure(
    cfg: &Config,
    worker: &mut Worker,
    kind: Failure,
    why: &str,
    folder: &str,
    text: &str,
    origin: Origin,
    index: u64,
) -> std::io::Result<PathBuf> {
    let small = if cfg.minimize && origin != Origin::Regression {
        minimize(cfg, worker, kind, folder, text)
    } else {
        text.to_string()
    };
    std::fs::create_dir_all(&cfg.found)?;
    let name = format!("{}-{:016x}", kind.word(), fnv(small.as_bytes()));
    let path = cfg.found.join(format!("{name}.die"));
    std::fs::write(&path, &small)?;
    let mut note = std::fs::File::create(cfg.found.join(format!("{name}.txt")))?;
    writeln!(
        note,
        "{}: {why}\nfolder: {folder}\norigin: {origin:?}, seed {}, input {index}\noriginal size {} bytes, minimized {} bytes",
        kind.word(),
        cfg.seed,
        text.len(),
        small.len()
    )?;
    Ok(path)
}

/// The smallest text found (by removing chunks of lines, then of characters) that still
/// fails the same way. Bounded: a hang costs a whole time budget per try.
fn minimize(cfg: &Config, worker: &mut Worker, kind: Failure, folder: &str, text: &str) -> String {
    let mut tries = if kind == Failure::Hang { 12 } else { 300 };
    let mut fails = |candidate: &str, tries: &mut usize| -> bool {
        if *tries == 0 {
            return false;
        }
        *tries -= 1;
        let v = worker.run(cfg, folder, candidate);
        failure(&v, cfg).is_some_and(|(k, _)| k == kind)
    };
    let mut best = text.to_string();
    // Lines, then characters: remove chunks of halving size while that keeps failing.
    for by_lines in [true, false] {
        let units = |s: &str| -> Vec<String> {
            if by_lines {
                s.split_inclusive('\n').map(str::to_string).collect()
            } else {
                s.chars().map(String::from).collect()
            }
        };
        let mut parts = units(&best);
        let mut chunk = parts.len() / 2;
        while chunk >= 1 && tries > 0 {
            let mut start = 0;
            let mut removed_any = false;
            while start < parts.len() && tries > 0 {
                let end = (start + chunk).min(parts.len());
                let candidate: String = parts[..start].concat() + &parts[end..].concat();
                if fails(&candidate, &mut tries) {
                    parts.drain(start..end);
                    removed_any = true;
                } else {
                    start = end;
                }
            }
            if !removed_any {
                chunk /= 2;
            }
        }
        best = parts.concat();
        // Characters are many: only minimize by them once the lines are few.
        if best.len() > 20_000 {
            break;
        }
    }
    best
}

/// FNV-1a, for a saved input's name.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Input `index` of a run, for `dieface-fuzz show`.
pub fn show(cfg: &Config, index: u64) -> (String, String) {
    let seeds = load_seeds(&cfg.corpus);
    let sig = Signatures::standard();
    let (folder, text, _) = make_input(cfg, &seeds, &sig, index);
    (folder, text)
}

/// Runs given files (each in the folder given, or `generated`) and prints how each
/// ended; true when none failed.
pub fn replay(cfg: &Config, files: &[PathBuf], folder: &str) -> std::io::Result<bool> {
    let scratch = std::env::temp_dir().join(format!("dieface-fuzz-{}-replay", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    let mut worker = Worker::start(cfg, &scratch)?;
    let mut ok = true;
    for f in files {
        let text = std::fs::read_to_string(f)?;
        let v = worker.run(cfg, folder, &text);
        match failure(&v, cfg) {
            Some((kind, why)) => {
                ok = false;
                println!("{}: {} ({why})", f.display(), kind.word());
            }
            None => println!("{}: {v:?}", f.display()),
        }
    }
    drop(worker);
    let _ = std::fs::remove_dir_all(&scratch);
    Ok(ok)
}
