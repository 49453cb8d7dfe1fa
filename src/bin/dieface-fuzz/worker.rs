//! The worker: a child process that runs inputs one after another, in-process, through
//! everything a user's command does (parse, evaluate, die model, tessellate, encode glb,
//! glTF, OBJ and STEP, `inspect` text and JSON, diagnostics rendered as the terminal
//! shows them), and reports each input's outcome, time and peak memory to the parent.
//!
//! The parent owns the budgets: it kills a worker that takes too long, and a worker that
//! runs out of address space (its `RLIMIT_AS`, set here) dies with the allocator's
//! message. Panics are caught here and reported with their message.
//!
//! Frames from the parent on stdin: `u32` little-endian length and bytes of the folder
//! (relative to the scratch copy of the corpus) the input is placed in, then the same
//! for the input's text. One reply line per input on stdout:
//! `done <clean|problems|panic> <microseconds> <peak KiB> <panic message>`.

use std::io::{self, BufWriter, Read, Write};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use dieface::eval::Engine;
use dieface::export::gltf::GltfCache;
use dieface::export::Format;
use dieface::limits::Limit;
use dieface::pipeline::report::{inspect_json, inspect_lines};
use dieface::pipeline::{encode_output, Output, Pipeline};

/// The file name an input is written to, inside its folder of the scratch corpus.
pub const INPUT_NAME: &str = "fuzz_input.die";

/// The message of the last panic, recorded by the hook instead of printed.
static PANIC: Mutex<Option<String>> = Mutex::new(None);

/// How one input ended.
pub enum Class {
    /// No diagnostics; every output encoded.
    Clean,
    /// Diagnostics (the expected end of most inputs).
    Problems,
    /// A panic, with its message and place.
    Panic(String),
}

impl Class {
    fn word(&self) -> &'static str {
        match self {
            Class::Clean => "clean",
            Class::Problems => "problems",
            Class::Panic(_) => "panic",
        }
    }
}

/// Serves inputs from stdin until it closes. `scratch` holds a copy of the corpus
/// folders, so inputs that import modules or read OBJ files find them.
pub fn serve(scratch: &Path, address_space_mb: u64) -> io::Result<()> {
    limit_address_space(address_space_mb);
    panic::set_hook(Box::new(|info| {
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into());
        if let Ok(mut p) = PANIC.lock() {
            *p = Some(format!("{message}{place}"));
        }
    }));
    let mut stdin = io::stdin().lock();
    let mut stdout = BufWriter::new(io::stdout().lock());
    while let Some(folder) = read_frame(&mut stdin)? {
        let Some(text) = read_frame(&mut stdin)? else {
            break;
        };
        let folder = String::from_utf8_lossy(&folder).into_owned();
        reset_peak_memory();
        let start = Instant::now();
        let class = match panic::catch_unwind(AssertUnwindSafe(|| run_one(scratch, &folder, &text)))
        {
            Ok(c) => c,
            Err(_) => Class::Panic(
                PANIC
                    .lock()
                    .ok()
                    .and_then(|mut p| p.take())
                    .unwrap_or_else(|| "a panic".into()),
            ),
        };
        let micros = start.elapsed().as_micros();
        let message = match &class {
            Class::Panic(m) => m.replace(['\n', '\r'], " "),
            _ => String::new(),
        };
        writeln!(
            stdout,
            "done {} {micros} {} {message}",
            class.word(),
            peak_memory_kib()
        )?;
        stdout.flush()?;
    }
    Ok(())
}

/// Reads one length-prefixed frame; `None` at the end of the input.
fn read_frame(r: &mut impl Read) -> io::Result<Option<Vec<u8>>> {
    let mut len = [0u8; 4];
    match r.read_exact(&mut len) {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e),
    }
    let mut buf = vec![0u8; u32::from_le_bytes(len) as usize];
    r.read_exact(&mut buf)?;
    Ok(Some(buf))
}

/// Writes one length-prefixed frame.
pub fn write_frame(w: &mut impl Write, bytes: &[u8]) -> io::Result<()> {
    let len = u32::try_from(bytes.len()).map_err(|_| io::Error::other("frame over 4 GiB"))?;
    w.write_all(&len.to_le_bytes())?;
    w.write_all(bytes)
}

/// The `mesh_vertices` limit inputs run with: a tenth of the default. Every other limit
/// is at its default. A script may ask for a mesh as large as the limit allows, and
/// the default (20 million vertices, a GLB of half a gigabyte) takes longer than the
/// time budget to tessellate and encode four times over; a tenth of it fits, and what
/// the run checks is that the limits bound the work, whatever their values.
const FUZZ_MESH_VERTICES: u64 = 2_000_000;

/// The `memory_mb` limit inputs run with: half the default memory budget of a run
/// (2 GiB), so an evaluation that grows without bound is stopped by the limit, with its
/// diagnostic, before the worker's budget is reached (encoding and `inspect` hold more
/// beside it).
const FUZZ_MEMORY_MB: u64 = 1024;

/// Runs one input the way `build`, `inspect` and `inspect --json` do.
fn run_one(scratch: &Path, folder: &str, text: &[u8]) -> Class {
    let dir = scratch.join(folder);
    let path: PathBuf = dir.join(INPUT_NAME);
    if std::fs::create_dir_all(&dir).is_err() || std::fs::write(&path, text).is_err() {
        return Class::Panic(format!("the worker cannot write {}", path.display()));
    }
    let mut engine = Engine::new(Some(scratch.to_path_buf()));
    let mut limits = *engine.limits();
    limits.set(Limit::MeshVertices, FUZZ_MESH_VERTICES);
    limits.set(Limit::MemoryMb, FUZZ_MEMORY_MB);
    engine.set_limits(limits);
    let mut pipeline = Pipeline::new(engine);
    let build = match pipeline.build(&path, None, &mut |_| {}) {
        Ok(b) => b,
        // An unreadable script (invalid UTF-8, say) is a usage error of the command.
        Err(_) => return Class::Problems,
    };
    let sources = &pipeline.engine.sources;
    for d in &build.problems {
        std::hint::black_box(sources.render(d, false));
    }
    std::hint::black_box(inspect_lines(&build.outcome, sources, &[]));
    let _ = std::hint::black_box(serde_json::to_vec(&inspect_json(
        &build.outcome,
        sources,
        &[],
    )));
    if !build.problems.is_empty() {
        return Class::Problems;
    }
    let mut cache = GltfCache::default();
    let outputs = [
        Output::Scene(Format::Glb),
        Output::Scene(Format::Gltf),
        Output::Scene(Format::Obj),
        Output::Step,
    ];
    let mut clean = true;
    for output in outputs {
        // A STEP file the die face cannot be sewn into is reported, not a crash.
        clean &= std::hint::black_box(encode_output(&build, output, "fuzz", &mut cache)).is_ok();
    }
    if clean {
        Class::Clean
    } else {
        Class::Problems
    }
}

/// Caps the worker's address space, so an input that allocates without bound ends this
/// process (and is reported) instead of the machine.
fn limit_address_space(mb: u64) {
    let bytes = mb.saturating_mul(1 << 20) as libc::rlim_t;
    let limit = libc::rlimit {
        rlim_cur: bytes,
        rlim_max: bytes,
    };
    // SAFETY: setrlimit reads the struct we pass and changes only this process.
    unsafe {
        libc::setrlimit(libc::RLIMIT_AS, &limit);
    }
}

/// Resets the kernel's record of this process's peak resident memory (Linux
/// `clear_refs` 5), so the next reading is the peak of one input.
fn reset_peak_memory() {
    // Give the heap the last input freed back to the system first: the allocator keeps
    // it otherwise, and the next input's peak would start from the last one's (a run
    // once blamed a 27-byte script for 2.3 GB).
    // SAFETY: malloc_trim only releases free memory of the process's own heap.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    unsafe {
        libc::malloc_trim(0);
    }
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The peak resident memory since the last reset, in KiB (0 where unknown).
fn peak_memory_kib() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse().ok())
        })
        .unwrap_or(0)
}
