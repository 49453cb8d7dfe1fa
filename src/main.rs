//! The `dieface` executable.

fn main() -> std::process::ExitCode {
    restore_sigpipe();
    dieface::cli::main()
}

/// Rust ignores SIGPIPE, so writing to a closed pipe (`dieface inspect f.die | head`)
/// would fail every later `println!`; restoring the default ends the process quietly, as
/// other command-line tools do.
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called once at start-up before any thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_sigpipe() {}
