//! Which process a client id belongs to. Client ids are `(pid << 32) | n`
//! ([`super::ShmClient`]), so an owner the core names only by its id can be named by its
//! program, for messages that say who holds control.

/// The process that made client `id`: its pid and program name (the base name of its
/// `argv[0]`, e.g. `mcm-gateway`, `mcm-ros2`), read from `/proc`; `None` when that process no
/// longer runs (or this is not Linux).
pub fn client_process(id: u64) -> Option<(u32, String)> {
    let pid = (id >> 32) as u32;
    let cmdline = std::fs::read(format!("/proc/{pid}/cmdline")).ok()?;
    let arg0 = cmdline.split(|b| *b == 0).next()?;
    let arg0 = String::from_utf8_lossy(arg0);
    let name = arg0.rsplit('/').next()?.to_string();
    (!name.is_empty()).then_some((pid, name))
}

#[cfg(test)]
mod tests {
    #[test]
    fn this_process_is_found_by_its_pid_and_a_dead_one_is_not() {
        let id = (u64::from(std::process::id()) << 32) | 7;
        let (pid, name) = super::client_process(id).expect("this process");
        assert_eq!(pid, std::process::id());
        assert!(!name.is_empty() && !name.contains('/'), "{name}");
        // pid_max is at most 2^22: this pid never exists.
        assert_eq!(super::client_process((1u64 << 31) << 32), None);
    }
}
