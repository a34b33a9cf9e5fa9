//! `mcm-gateway`: the JSON/TCP and telnet front end of the MCM. See `mcm-gateway --help`.

fn main() -> std::process::ExitCode {
    mcm_gateway::cli::main(std::env::args_os())
}
