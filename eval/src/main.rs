//! `texel-eval`: measures every render method along scripted camera paths and writes
//! `report.json` and charts. All the work is in the `texel_eval` library; see `cli`.

mod cli;
mod scale_cli;

fn main() -> std::process::ExitCode {
    match cli::main() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
