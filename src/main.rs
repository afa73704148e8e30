//! The `realist` command line. Rendering logic lives in the library; this file only parses
//! arguments, runs subcommands and maps errors to exit codes.

mod cli;

fn main() -> std::process::ExitCode {
    #[cfg(feature = "viewer")]
    realist::viewer::mark_launch();
    match cli::run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("realist: {}", one_line(&e));
            std::process::ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line, leaving out a cause whose text the message already
/// contains (e.g. an I/O error that a load error quotes).
fn one_line(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.is_empty() {
            out = text;
        } else if !out.contains(&text) {
            out = format!("{out}: {text}");
        }
    }
    out.replace('\n', " ")
}

/// Output cut short by the reader (`realist info ... | head`) is not an error.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
