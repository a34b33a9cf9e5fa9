//! A virtual machine for the tests that need a real Linux kernel with SocketCAN (this machine's
//! has no CAN) or systemd as PID 1: QEMU, software emulation (TCG; KVM hangs under nested
//! virtualisation on these machines), booting the Debian guest that `scripts/vm/build-guest.sh`
//! builds and caches outside the work tree, in `~/.cache/mcm/vm/` (docs/testing.md, "The virtual
//! machine").
//!
//! [`image`] builds or finds the guest (or says which tool is missing: the test skips, or fails
//! under `CI`). [`Guest::boot`] starts QEMU on a per-guest qcow2 overlay of the cached image (the
//! cache never changes) with:
//! - a host directory shared read-only at [`GUEST_RO`] (9p; tests share the workspace's target
//!   directory, [`target_dir`], so that the guest runs binaries built on the host:
//!   [`Guest::guest_path`] names a host file there as the guest sees it);
//! - a writable directory at [`GUEST_RW`] ([`Guest::results`] on the host), through which the
//!   guest's agent (`scripts/vm/rootfs/usr/local/sbin/mcm-guest-agent`) takes commands:
//!   [`Guest::run`] runs a shell script as root in the guest and returns its exit status and
//!   output, within a bounded wait;
//! - guest TCP ports forwarded to free loopback ports of the host ([`Guest::host_port`]); QEMU's
//!   user network with `restrict=on`: the guest reaches nothing outside.
//!
//! Every byte the guest prints on its serial console (and QEMU's own messages) goes to a log
//! file under `target/tmp/`, named in every panic. [`Guest::reboot`] reboots (a cold boot: QEMU
//! is started again) and waits for the agent of the new boot; [`Guest::shutdown`] powers off;
//! dropping a guest kills QEMU.
//!
//! QEMU crashing (ended by a signal: its own assertion or fault) is told apart from the guest's
//! or the MCM's failures in every message. A boot in which QEMU crashed before the guest's agent
//! answered is started once more, said on stderr and in the console log, and counted
//! ([`Guest::emulator_crashes`]); a second crash in the same boot, or one after the agent
//! answered, fails the test with QEMU's own words.

use std::ffi::{OsStr, OsString};
use std::fs;
use std::io::{Read, Write};
use std::net::TcpListener;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Where the guest mounts the read-only share.
pub const GUEST_RO: &str = "/mnt/mcm-ro";
/// Where the guest mounts the writable share ([`Guest::results`] on the host).
pub const GUEST_RW: &str = "/mnt/mcm-rw";

/// The longest a boot (or a reboot) may take until the agent is ready: software emulation on a
/// loaded two-core machine.
pub const BOOT_WAIT: Duration = Duration::from_secs(300);
/// The longest building the guest may take (from scratch: debootstrap downloads and unpacks
/// about 200 packages).
const BUILD_WAIT: Duration = Duration::from_secs(40 * 60);
/// The longest a power-off may take.
const SHUTDOWN_WAIT: Duration = Duration::from_secs(120);
/// How often the host looks at the shared directory.
const POLL: Duration = Duration::from_millis(50);

/// The built guest: the directory holding `vmlinuz`, `initrd.img` and `rootfs.img`.
#[derive(Debug, Clone)]
pub struct Image {
    pub dir: PathBuf,
}

/// The workspace's target directory, which the guest shares.
pub use super::built::target_dir;

/// Build the guest, or find it built (`scripts/vm/build-guest.sh`, cached in `~/.cache/mcm/vm/`
/// or `$MCM_VM_CACHE`). `Err` says which tool is missing (the caller skips: `super::skip`); a
/// build that fails otherwise panics with the script's output.
pub fn image() -> Result<Image, String> {
    for tool in [QEMU, "qemu-img"] {
        if super::find_program(tool).is_none() {
            return Err(format!(
                "{tool} is not installed (Debian: apt-get install qemu-system-x86 qemu-utils; \
                 .ci/run installs it)"
            ));
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/vm/build-guest.sh");
    let mut child = Command::new("bash")
        .arg(&script)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", script.display()));
    let stdout = read_all(child.stdout.take().unwrap());
    let stderr = read_all(child.stderr.take().unwrap());
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait for the guest build") {
            break Some(s);
        }
        if started.elapsed() > BUILD_WAIT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    let stdout = stdout.join().unwrap_or_default();
    let stderr = stderr.join().unwrap_or_default();
    match status {
        Some(s) if s.success() => {
            let dir = PathBuf::from(stdout.lines().last().unwrap_or_default().trim());
            assert!(
                dir.join("rootfs.img").is_file(),
                "{} printed {dir:?}, which has no rootfs.img:\n{stdout}{stderr}",
                script.display()
            );
            if started.elapsed() > Duration::from_secs(5) {
                // A build happened: say what it cost (shown with --nocapture).
                eprintln!("{stderr}");
            }
            Ok(Image { dir })
        }
        // The script's exit status for "a tool (or root) is missing".
        Some(s) if s.code() == Some(2) => Err(stderr.trim().to_owned()),
        Some(s) => panic!("{} failed ({s}):\n{stderr}", script.display()),
        None => panic!(
            "{} did not finish within {BUILD_WAIT:?}:\n{stderr}",
            script.display()
        ),
    }
}

fn read_all(mut from: impl Read + Send + 'static) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = from.read_to_end(&mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

/// What a command run in the guest ended with.
#[derive(Debug, Clone)]
pub struct Run {
    /// The shell's exit status.
    pub status: i32,
    /// Its standard output and standard error, interleaved as written.
    pub output: String,
}

/// A running guest; dropping it kills QEMU.
pub struct Guest {
    /// The name the test gave it, in its messages.
    tag: String,
    qemu: Child,
    /// The program run as QEMU, and its arguments, for starting it again after a reboot.
    qemu_program: OsString,
    qemu_args: Vec<OsString>,
    /// This guest's directory under `target/tmp/`: the overlay, the log, the writable share.
    dir: PathBuf,
    log: PathBuf,
    ro: PathBuf,
    rw: PathBuf,
    /// (guest port, host port).
    forwards: Vec<(u16, u16)>,
    boot_id: String,
    next_command: u32,
    /// How often QEMU crashed before a boot's agent answered (each such boot started once more).
    emulator_crashes: u32,
}

/// Whether QEMU ended by a signal: its own assertion (SIGABRT) or fault, never the guest going
/// down (exit status 0) or QEMU refusing its arguments (an exit code).
fn crashed(status: ExitStatus) -> bool {
    status.signal().is_some()
}

/// A free TCP port on the host's loopback (bound, then released for QEMU to take).
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free loopback port")
}

/// QEMU's accelerator: software emulation, a host thread per vCPU (QEMU's default on x86).
pub const ACCEL: &str = "tcg";

/// The guest kernel's command line. `maxcpus=1`: the second CPU stays offline while the kernel
/// probes and enables the PCI devices, where two running vCPUs can make QEMU's multi-threaded
/// TCG abort (docs/testing.md, "QEMU's abort on a boot, and how the guest avoids it"); the guest
/// brings it online once udev has settled
/// (`scripts/vm/rootfs/etc/systemd/system/mcm-guest-cpus.service`).
const KERNEL_CMDLINE: &str = "console=ttyS0,115200 root=/dev/vda rw maxcpus=1";

/// The guest's CPUs (`-smp`), all online once it has booted.
const CPUS: &str = "2";

/// The emulator [`Guest::boot`] runs.
pub const QEMU: &str = "qemu-system-x86_64";

/// The weight QEMU's session is given against the host's other sessions (`nice` of its
/// autogroup, `sched(7)`), where the test runs as root.
const QEMU_AUTOGROUP_NICE: &str = "-10";

/// Start `program` (QEMU) with `args`, its standard output and error appended to `log`.
///
/// QEMU runs in a session of its own whose autogroup weighs more than the others: with Linux's
/// autogroups (`/proc/sys/kernel/sched_autogroup_enabled`) every session gets an equal share
/// of the CPUs whatever its processes' `nice`, so that other work on the host (a build in
/// another terminal) would take the emulated CPUs' time and the guest's MCM would miss its
/// drives' reports. Without root the weight stays as it is (said once in the log). Out of the
/// terminal's process group, QEMU would outlive a Ctrl-C of the tests: it is killed when the
/// test's thread that started it ends (`PR_SET_PDEATHSIG`; a [`Guest`] lives in one test's
/// thread).
fn spawn_qemu(program: &OsStr, args: &[OsString], log: &Path) -> Child {
    let log_file = fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
        .expect("open the guest's log");
    let mut cmd = Command::new(program);
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(log_file.try_clone().expect("the guest's log, twice"))
        .stderr(log_file.try_clone().expect("the guest's log, three times"));
    // SAFETY: `setsid` and `prctl` are async-signal-safe system calls that touch no memory of
    // the parent; they run in the child between fork and exec, as `pre_exec` requires.
    unsafe {
        cmd.pre_exec(|| {
            if libc::setsid() == -1
                || libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL as libc::c_ulong) == -1
            {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", program.display()));
    let autogroup = format!("/proc/{}/autogroup", child.id());
    if let Err(e) = fs::write(&autogroup, QEMU_AUTOGROUP_NICE) {
        let mut log_file = log_file;
        let _ = writeln!(
            log_file,
            "[harness] QEMU's session keeps the default CPU weight ({autogroup}: {e})"
        );
    }
    child
}

impl Guest {
    /// Boot `image` (2 vCPUs, 1 GiB) with `ro_share` shared read-only at [`GUEST_RO`] and each
    /// of `forward` (guest TCP ports) reachable on the host at [`Guest::host_port`]; returns
    /// once the guest's agent is ready, or panics after [`BOOT_WAIT`].
    pub fn boot(tag: &str, image: &Image, ro_share: &Path, forward: &[u16]) -> Guest {
        Guest::boot_with(OsStr::new(QEMU), tag, image, ro_share, forward)
    }

    /// [`Guest::boot`] with `program` run as QEMU: a stand-in, for the harness's own tests.
    pub fn boot_with(
        program: &OsStr,
        tag: &str,
        image: &Image,
        ro_share: &Path,
        forward: &[u16],
    ) -> Guest {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("vm-{}", super::unique_instance(tag)));
        let rw = dir.join("rw");
        fs::create_dir_all(rw.join("agent")).expect("make the guest's directory");
        let log = dir.join("console.log");
        let disk = dir.join("disk.qcow2");
        let out = Command::new("qemu-img")
            .args(["create", "-q", "-f", "qcow2", "-F", "raw", "-b"])
            .arg(image.dir.join("rootfs.img"))
            .arg(&disk)
            .output()
            .expect("run qemu-img");
        assert!(
            out.status.success(),
            "qemu-img create of {} failed: {}",
            disk.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let ro = ro_share
            .canonicalize()
            .unwrap_or_else(|e| panic!("the read-only share {}: {e}", ro_share.display()));
        let forwards: Vec<(u16, u16)> = forward.iter().map(|&g| (g, free_port())).collect();
        let mut netdev = "user,id=net0,restrict=on".to_owned();
        for (g, h) in &forwards {
            netdev.push_str(&format!(",hostfwd=tcp:127.0.0.1:{h}-10.0.2.15:{g}"));
        }
        let mut args: Vec<OsString> = Vec::new();
        let mut arg = |a: &dyn AsRef<OsStr>| args.push(a.as_ref().to_owned());
        for a in ["-nodefaults", "-no-user-config", "-display", "none"] {
            arg(&a);
        }
        // `MCM_VM_ACCEL` chooses another accelerator by hand (e.g. `tcg,thread=single`).
        let accel = std::env::var("MCM_VM_ACCEL").unwrap_or_else(|_| ACCEL.to_owned());
        for a in ["-machine", "q35", "-accel", &accel, "-cpu", "max"] {
            arg(&a);
        }
        for a in ["-smp", CPUS, "-m", "1024"] {
            arg(&a);
        }
        // A reboot in the guest ends QEMU; [`Guest::reboot`] starts it again (see there).
        arg(&"-no-reboot");
        arg(&"-kernel");
        arg(&image.dir.join("vmlinuz"));
        arg(&"-initrd");
        arg(&image.dir.join("initrd.img"));
        arg(&"-append");
        // `MCM_VM_CMDLINE` replaces it by hand (e.g. without `maxcpus=1`, to compare).
        arg(&std::env::var("MCM_VM_CMDLINE").unwrap_or_else(|_| KERNEL_CMDLINE.to_owned()));
        arg(&"-drive");
        arg(&format!(
            "file={},format=qcow2,if=virtio,cache=unsafe",
            disk.display()
        ));
        arg(&"-virtfs");
        arg(&format!(
            "local,path={},mount_tag=mcmro,security_model=none,readonly=on,multidevs=remap",
            ro.display()
        ));
        arg(&"-virtfs");
        arg(&format!(
            "local,path={},mount_tag=mcmrw,security_model=none",
            rw.display()
        ));
        arg(&"-netdev");
        arg(&netdev);
        arg(&"-device");
        arg(&"virtio-net-pci,netdev=net0,romfile=");
        arg(&"-chardev");
        arg(&format!("file,id=con,path={},append=on", log.display()));
        arg(&"-serial");
        arg(&"chardev:con");
        let qemu = spawn_qemu(program, &args, &log);
        let mut guest = Guest {
            tag: tag.to_owned(),
            qemu,
            qemu_program: program.to_owned(),
            qemu_args: args,
            dir,
            log,
            ro,
            rw,
            forwards,
            boot_id: String::new(),
            next_command: 0,
            emulator_crashes: 0,
        };
        let started = Instant::now();
        guest.wait_boot(true);
        eprintln!(
            "guest {tag}: agent ready {:.1} s after QEMU started; log {}",
            started.elapsed().as_secs_f64(),
            guest.log.display()
        );
        guest
    }

    /// The file with everything the guest printed on its console (and QEMU's messages).
    pub fn log(&self) -> &Path {
        &self.log
    }

    /// The host side of the writable share ([`GUEST_RW`] in the guest).
    pub fn results(&self) -> &Path {
        &self.rw
    }

    /// The host port that reaches the guest's TCP port `guest_port` (one of `forward`).
    pub fn host_port(&self, guest_port: u16) -> u16 {
        self.forwards
            .iter()
            .find(|(g, _)| *g == guest_port)
            .unwrap_or_else(|| {
                panic!(
                    "guest port {guest_port} is not forwarded; forwarded: {:?}",
                    self.forwards
                )
            })
            .1
    }

    /// `host_path`, a file in the read-only share, as the guest sees it.
    pub fn guest_path(&self, host_path: &Path) -> String {
        let p = host_path
            .canonicalize()
            .unwrap_or_else(|e| panic!("{}: {e}", host_path.display()));
        let rel = p.strip_prefix(&self.ro).unwrap_or_else(|_| {
            panic!(
                "{} is not in the read-only share {}",
                p.display(),
                self.ro.display()
            )
        });
        format!("{GUEST_RO}/{}", rel.display())
    }

    /// Panic with `what`, the log's path and its last lines.
    fn fail(&self, what: &str) -> ! {
        let text = fs::read(&self.log).unwrap_or_default();
        let text = String::from_utf8_lossy(&text);
        let lines: Vec<&str> = text.lines().collect();
        let tail = lines[lines.len().saturating_sub(40)..].join("\n");
        panic!(
            "{what}\nthe guest's console log: {}\nits last lines:\n{tail}",
            self.log.display()
        )
    }

    /// How often QEMU crashed before a boot's agent answered, each time started once more (0
    /// in a healthy run: `reboots::reboots_in_a_row` requires it).
    pub fn emulator_crashes(&self) -> u32 {
        self.emulator_crashes
    }

    /// What QEMU itself printed (its lines start with its program name), the last few.
    fn qemu_words(&self) -> String {
        let text = fs::read(&self.log).unwrap_or_default();
        let text = String::from_utf8_lossy(&text);
        let words: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("qemu-system"))
            .collect();
        if words.is_empty() {
            "(nothing in the log)".to_owned()
        } else {
            words[words.len().saturating_sub(5)..].join("\n")
        }
    }

    /// Words for QEMU having ended with `status` while `while_doing`: a crash (a signal) is named
    /// as the emulator's fault, with QEMU's own words.
    fn ended(&self, status: ExitStatus, while_doing: &str) -> String {
        if crashed(status) {
            format!(
                "QEMU itself crashed ({status}) while {while_doing}: a fault of the emulator, not \
                 of the MCM or the guest; QEMU said:\n{}",
                self.qemu_words()
            )
        } else {
            format!("QEMU ended ({status}) while {while_doing}")
        }
    }

    /// Panics (naming the log) when QEMU has ended.
    fn check_running(&mut self, while_doing: &str) {
        if let Some(status) = self.qemu.try_wait().expect("wait for QEMU") {
            self.fail(&self.ended(status, while_doing));
        }
    }

    /// After QEMU crashed (`status`) in a boot before the agent answered: count it, say so on
    /// stderr and in the console log, and start QEMU again on the same disk.
    fn restart_after_crash(&mut self, status: ExitStatus, while_doing: &str) {
        self.emulator_crashes += 1;
        let said = format!(
            "guest {}: {}\nstarting QEMU once more on the same disk (log {})",
            self.tag,
            self.ended(status, while_doing),
            self.log.display()
        );
        eprintln!("{said}");
        if let Ok(mut log) = fs::OpenOptions::new().append(true).open(&self.log) {
            let _ = writeln!(log, "\n=== test harness: {said}");
        }
        self.qemu = spawn_qemu(&self.qemu_program, &self.qemu_args, &self.log);
    }

    /// Wait until the agent says it is ready in a boot other than the last one seen. With
    /// `may_retry`, a QEMU that crashes before then is started once more
    /// ([`Guest::restart_after_crash`]); a second crash fails.
    fn wait_boot(&mut self, mut may_retry: bool) {
        let mut started = Instant::now();
        let boot_file = self.rw.join("agent/boot");
        loop {
            if let Some(status) = self.qemu.try_wait().expect("wait for QEMU") {
                if !(may_retry && crashed(status)) {
                    self.fail(&self.ended(status, "waiting for the guest's agent"));
                }
                may_retry = false;
                self.restart_after_crash(status, "waiting for the guest's agent");
                started = Instant::now();
            }
            if let Ok(id) = fs::read_to_string(&boot_file) {
                let id = id.trim();
                if !id.is_empty() && id != self.boot_id {
                    self.boot_id = id.to_owned();
                    return;
                }
            }
            if started.elapsed() > BOOT_WAIT {
                self.fail(&format!(
                    "the guest's agent was not ready within {BOOT_WAIT:?} ({} has no new boot id)",
                    boot_file.display()
                ));
            }
            std::thread::sleep(POLL);
        }
    }

    /// Hand `script` to the agent; returns the command's path without extension.
    fn submit(&mut self, script: &str) -> PathBuf {
        self.next_command += 1;
        let base = self.rw.join(format!("agent/c{}", self.next_command));
        let tmp = base.with_extension("tmp");
        let mut f = fs::File::create(&tmp).expect("write a command for the guest");
        f.write_all(script.as_bytes()).unwrap();
        drop(f);
        fs::rename(&tmp, base.with_extension("cmd")).expect("hand the command to the guest");
        base
    }

    /// Run `script` with bash as root in the guest (working directory `/`); its exit status and
    /// output, or `Err` (with the output so far) when it did not end within `wait`. Panics when
    /// QEMU ends meanwhile.
    pub fn try_run(&mut self, script: &str, wait: Duration) -> Result<Run, String> {
        let base = self.submit(script);
        let started = Instant::now();
        let status_file = base.with_extension("status");
        loop {
            if let Ok(s) = fs::read_to_string(&status_file) {
                let status = s.trim().parse().unwrap_or_else(|e| {
                    self.fail(&format!("{}: {e}: {s:?}", status_file.display()))
                });
                let output = fs::read(base.with_extension("out")).unwrap_or_default();
                return Ok(Run {
                    status,
                    output: String::from_utf8_lossy(&output).into_owned(),
                });
            }
            self.check_running(&format!("running {script:?}"));
            if started.elapsed() > wait {
                let output = fs::read(base.with_extension("out")).unwrap_or_default();
                let taken = base.with_extension("run").exists();
                return Err(format!(
                    "{script:?} did not end within {wait:?} in the guest ({}); its output so far:\n{}",
                    if taken {
                        "the agent started it"
                    } else {
                        "the agent never took it"
                    },
                    String::from_utf8_lossy(&output)
                ));
            }
            std::thread::sleep(POLL);
        }
    }

    /// [`Guest::try_run`], panicking (with the log) when the script does not end within `wait`.
    pub fn run(&mut self, script: &str, wait: Duration) -> Run {
        self.try_run(script, wait).unwrap_or_else(|e| self.fail(&e))
    }

    /// [`Guest::run`], panicking (with the output and the log) unless the script exits with 0;
    /// returns its output.
    pub fn run_ok(&mut self, script: &str, wait: Duration) -> String {
        let r = self.run(script, wait);
        if r.status != 0 {
            self.fail(&format!(
                "{script:?} exited with {} in the guest; its output:\n{}",
                r.status, r.output
            ));
        }
        r.output
    }

    /// Reboot the guest (`systemctl reboot`) and wait until its agent is ready again, in a new
    /// boot. The disk, the shares and the forwarded ports stay.
    ///
    /// The guest shuts down as for any reboot; QEMU (run with `-no-reboot`) then ends and is
    /// started again on the same disk, so the second boot is a cold boot like the first. A warm
    /// reset under software emulation once left the second kernel's timers dead (CI, 2026-11-26:
    /// "rcu_preempt kthread timer wakeup didn't happen", the agent never came back within
    /// [`BOOT_WAIT`]); the first boot never showed it. Panics (with the log) when the guest does
    /// not go down within two minutes or QEMU ends with a failure.
    ///
    /// QEMU crashing while the guest goes down counts as the boot's one crash
    /// ([`Guest::emulator_crashes`]): it is started again as it would be anyway, and a crash in
    /// the new boot before its agent answers then fails.
    pub fn reboot(&mut self) {
        self.submit("systemctl reboot");
        let status = self.wait_qemu_end("reboot");
        let may_retry = if crashed(status) {
            self.restart_after_crash(status, "the guest went down for its reboot");
            false
        } else {
            if !status.success() {
                self.fail(&format!("QEMU ended with {status} on the guest's reboot"));
            }
            self.qemu = spawn_qemu(&self.qemu_program, &self.qemu_args, &self.log);
            true
        };
        self.wait_boot(may_retry);
    }

    /// After [`Guest::reboot`] (which waits for the agent of a new boot, by its boot id): the
    /// boot completed and vcan0 is up again; panics with what differs and the log.
    pub fn check_rebooted(&mut self) {
        let boot = Boot::of(self);
        assert!(
            boot.running && boot.vcan0_up && boot.cpus == CPUS,
            "after the reboot, the boot completed, vcan0 up, {CPUS} CPUs online: {}\n(log: {})",
            boot.said,
            self.log().display()
        );
    }

    /// Wait for QEMU to end after the guest was told to `what`; panics (with the log) after
    /// [`SHUTDOWN_WAIT`].
    fn wait_qemu_end(&mut self, what: &str) -> ExitStatus {
        let started = Instant::now();
        loop {
            if let Some(status) = self.qemu.try_wait().expect("wait for QEMU") {
                return status;
            }
            if started.elapsed() > SHUTDOWN_WAIT {
                self.fail(&format!(
                    "the guest did not go down for its {what} within {SHUTDOWN_WAIT:?}"
                ));
            }
            std::thread::sleep(POLL);
        }
    }

    /// Power the guest off (`systemctl poweroff`) and wait for QEMU to end; returns QEMU's
    /// exit status. Panics (with the log) when it does not end within two minutes.
    pub fn shutdown(mut self) -> ExitStatus {
        self.submit("systemctl poweroff");
        self.wait_qemu_end("power-off")
    }
}

/// Kills QEMU if it still runs and removes the overlay disk (the log and the writable share
/// stay under `target/tmp/`).
impl Drop for Guest {
    fn drop(&mut self) {
        if self.qemu.try_wait().ok().flatten().is_none() {
            let _ = self.qemu.kill();
            let _ = self.qemu.wait();
        }
        let _ = fs::remove_file(self.dir.join("disk.qcow2"));
    }
}

/// What the tests that run the MCM in a guest rely on, checked in `guest` (booted with
/// [`target_dir`] as its read-only share); panics with what differs and the log:
/// - systemd is PID 1, the boot completed (`running`), vcan0 is up;
/// - the read-only share reads a file the host wrote and refuses writes, and what the guest
///   writes to [`GUEST_RW`] reaches the host;
/// - the guest reaches nothing of the host's (QEMU's `restrict=on`): without it, 10.0.2.2 would
///   be the host's loopback, where a listener of this test waits.
pub fn check_the_guest(guest: &mut Guest) {
    const WAIT: Duration = Duration::from_secs(120);
    let log = guest.log().display().to_string();
    let boot = Boot::of(guest);
    assert!(
        boot.pid1 == "systemd" && boot.running && boot.vcan0_up && boot.cpus == CPUS,
        "PID 1 systemd, the boot completed, vcan0 up, {CPUS} CPUs online: {}\n(log: {log})",
        boot.said
    );

    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(super::unique_instance("vm-ro"));
    fs::create_dir_all(&dir).unwrap();
    let token = format!("from the host {}\n", std::process::id());
    fs::write(dir.join("shared.txt"), &token).unwrap();
    let ro = guest.guest_path(&dir);
    let out = guest.run(
        &format!(
            "cat {ro}/shared.txt && echo from the guest >{GUEST_RW}/guest.txt && ! touch {ro}/x"
        ),
        WAIT,
    );
    assert_eq!(out.status, 0, "the shares: {}\n(log: {log})", out.output);
    assert!(
        out.output.starts_with(&token),
        "the read-only share: {}",
        out.output
    );
    assert_eq!(
        fs::read_to_string(guest.results().join("guest.txt")).unwrap(),
        "from the guest\n"
    );
    assert!(
        !dir.join("x").exists(),
        "the guest wrote into the read-only share"
    );
    let _ = fs::remove_dir_all(&dir);

    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let out = guest.run(
        &format!(
            "python3 -c 'import socket; socket.create_connection((\"10.0.2.2\", {port}), timeout=5)' \
             && echo REACHED"
        ),
        WAIT,
    );
    assert!(
        out.status != 0 && !out.output.contains("REACHED"),
        "the guest reached the host's 127.0.0.1:{port}: {}\n(log: {log})",
        out.output
    );
    assert!(
        listener.accept().is_err(),
        "the host's listener got a connection from the guest"
    );
}

/// What a boot is: PID 1's name, whether systemd says the boot completed (`running`, waited
/// for), whether vcan0 is up, how many CPUs are online; and the guest's words for them.
struct Boot {
    pid1: String,
    running: bool,
    vcan0_up: bool,
    cpus: String,
    said: String,
}

impl Boot {
    fn of(guest: &mut Guest) -> Boot {
        let said = guest.run_ok(
            "cat /proc/1/comm; systemctl is-system-running --wait; ip -br link show vcan0; nproc",
            Duration::from_secs(120),
        );
        let line = |i: usize| said.lines().nth(i).unwrap_or("");
        let (pid1, running) = (line(0).to_string(), line(1) == "running");
        let vcan0_up = line(2).starts_with("vcan0") && line(2).contains("UP");
        Boot {
            pid1,
            running,
            vcan0_up,
            cpus: line(3).to_string(),
            said,
        }
    }
}

/// The executable of `package`'s library unit tests (in the directory `dir` of the workspace),
/// as `cargo test --workspace` (the test command) built it ([`super::built`]), so that a guest
/// sharing [`target_dir`] can run it.
pub fn lib_test_binary(package: &str, dir: &str) -> PathBuf {
    shared_path(
        super::built::Executable {
            name: &package.replace('-', "_"),
            kind: "lib",
            test: true,
            manifest: &format!("{dir}/Cargo.toml"),
        }
        .path(),
    )
}

/// The executable of the integration test `name` (the file of that name in `tests/`) of this
/// package, as [`lib_test_binary`] finds a unit-test executable.
pub fn integration_test_binary(name: &str) -> PathBuf {
    shared_path(
        super::built::Executable {
            name,
            kind: "test",
            test: true,
            manifest: "Cargo.toml",
        }
        .path(),
    )
}

/// `exe`, after checking that it is under the target directory the guest shares.
fn shared_path(exe: PathBuf) -> PathBuf {
    assert!(
        exe.starts_with(target_dir()),
        "{} is not under the target directory {} that the guest shares",
        exe.display(),
        target_dir().display()
    );
    exe
}
