//! The `dieface` executable.

fn main() -> std::process::ExitCode {
    dieface::cli::main()
}
