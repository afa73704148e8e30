//! The `realist` command line. Rendering logic lives in the library; this file only parses
//! arguments, runs subcommands and maps errors to exit codes.

mod cli;

fn main() -> std::process::ExitCode {
    match cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("realist: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Output cut short by the reader (`realist info ... | head`) is not an error.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
