fn main() -> std::process::ExitCode {
    mcm_virtual_arm::cli::main(std::env::args_os())
}
