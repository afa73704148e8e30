//! The `realist` command line. Rendering logic lives in the library; this file only parses
//! arguments, runs subcommands and maps errors to exit codes.

mod cli;

fn main() -> std::process::ExitCode {
    match cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("realist: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
