//! The `spectex` command: its code is the `spectex_cli` library (`src/lib.rs`), compiled once
//! for this program, the integration tests and the benches.

fn main() -> std::process::ExitCode {
    spectex_cli::main()
}
