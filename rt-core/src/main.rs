//! `mcm-rt`: the real-time core of the MCM. See `mcm-rt --help`.

fn main() -> std::process::ExitCode {
    mcm_rt_core::cli::main(std::env::args_os())
}
