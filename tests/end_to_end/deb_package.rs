//! The Debian package (docs/deploy.md, "The Debian package"), made by cargo-deb from the root
//! manifest's `[package.metadata.deb]`. Its one binary is this test build's `mcm`, placed where
//! `cargo deb --no-build` takes the release binary, in a target directory of the test's own: CI
//! compiles nothing twice (a real package is `cargo deb`, which builds the release binary). The
//! tests check the files and their modes, the links that make `mcm` the other programs, the
//! control fields, the conffile and the maintainer scripts, and `systemd-analyze verify` of
//! every unit unpacked over systemd's own units. The gateway's unit needs systemd 254
//! (`RestartSteps=`); on a host with an older one (Debian 12 has 252) systemd 254's
//! `systemd-analyze` and units are taken from bookworm-backports, unpacked under target/ (not
//! installed). A missing tool (cargo-deb, dpkg-deb) skips, or fails with CI set.

use crate::common;

use common::deb::run;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The programs in /usr/bin: `mcm` and the links to it.
const PROGRAMS: [&str; 5] = [
    "mcm",
    "mcm-rt",
    "mcm-gateway",
    "mcm-ros2",
    "mcm-virtual-arm",
];
/// The units in /usr/lib/systemd/system.
const UNITS: [&str; 4] = [
    "mcm.target",
    "mcm-rt.service",
    "mcm-gateway.service",
    "mcm-ros2.service",
];
/// Every other file of the package and its mode.
const FILES: [(&str, &str); 13] = [
    ("etc/mcm/prob2.toml", "-rw-r--r--"),
    (
        "usr/lib/systemd/system/mcm-rt.service.d/realtime.conf",
        "-rw-r--r--",
    ),
    (
        "usr/lib/systemd/system/mcm-rt.service.d/bus.conf",
        "-rw-r--r--",
    ),
    ("usr/lib/mcm/wait-for-bus", "-rwxr-xr-x"),
    ("usr/lib/systemd/network/80-mcm-can0.network", "-rw-r--r--"),
    ("usr/lib/systemd/network/80-mcm-can0.link", "-rw-r--r--"),
    ("usr/lib/sysusers.d/mcm.conf", "-rw-r--r--"),
    ("usr/lib/sysctl.d/60-mcm-realtime.conf", "-rw-r--r--"),
    ("usr/lib/tmpfiles.d/mcm-cpufreq.conf", "-rw-r--r--"),
    ("usr/share/doc/mcm/README.md", "-rw-r--r--"),
    ("usr/share/doc/mcm/deploy.md", "-rw-r--r--"),
    ("usr/share/doc/mcm/safety.md", "-rw-r--r--"),
    ("usr/share/doc/mcm/security.md", "-rw-r--r--"),
];

/// This test's own directory under target/.
fn work() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("deb-package")
}

fn text(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The package, built once per test process; `None` (after saying so, or failing with CI set)
/// when a tool is missing.
fn package(test: &str) -> Option<&'static Path> {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match BUILT.get_or_init(build) {
        Ok(p) => Some(p),
        Err(why) => {
            common::skip(test, why);
            None
        }
    }
}

fn build() -> Result<PathBuf, String> {
    if common::find_program("dpkg-deb").is_none() {
        return Err("dpkg-deb is not installed (Debian's dpkg)".into());
    }
    common::deb::cargo_deb_installed()?;
    let dir = work().join("build");
    Ok(common::deb::build(&dir, &[("mcm.deb", None)]).remove(0))
}

/// The package unpacked into a fresh directory `name` under the test's directory.
fn unpacked(deb: &Path, name: &str) -> PathBuf {
    let root = work().join(name);
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    run(Command::new("dpkg-deb").arg("-x").arg(deb).arg(&root));
    root
}

#[test]
fn the_package_holds_the_programs_units_configuration_and_docs() {
    let Some(deb) = package("the_package_holds_the_programs_units_configuration_and_docs") else {
        return;
    };
    let listing = text(&run(Command::new("dpkg-deb").arg("-c").arg(deb)));
    // `-rw-r--r-- root/root  1234 2026-01-01 00:00 ./etc/mcm/prob2.toml`, links `a -> b`.
    let entries: Vec<(&str, &str)> = listing
        .lines()
        .filter_map(|l| {
            let mode = l.split_whitespace().next()?;
            let path = l.split(" ./").nth(1)?;
            Some((mode, path))
        })
        .collect();
    let mode_of = |path: &str| {
        entries
            .iter()
            .find(|(_, p)| *p == path || p.starts_with(&format!("{path} -> ")))
            .map(|(m, p)| (*m, *p))
            .unwrap_or_else(|| panic!("{path} is not in the package:\n{listing}"))
    };
    assert_eq!(mode_of("usr/bin/mcm").0, "-rwxr-xr-x");
    for link in &PROGRAMS[1..] {
        let (mode, entry) = mode_of(&format!("usr/bin/{link}"));
        assert!(mode.starts_with('l'), "{entry}: a link");
        assert!(entry.ends_with(" -> mcm"), "{entry}: a link to mcm");
    }
    for unit in UNITS {
        assert_eq!(
            mode_of(&format!("usr/lib/systemd/system/{unit}")).0,
            "-rw-r--r--"
        );
    }
    for (path, mode) in FILES {
        assert_eq!(mode_of(path).0, mode, "{path}");
    }
    assert!(!listing.contains("usr/local"), "{listing}");
    // The unit's programs are there: the links resolve to `mcm`, which is each of them.
    let root = unpacked(deb, "programs");
    for program in PROGRAMS {
        let out = run(Command::new(root.join("usr/bin").join(program)).arg("--version"));
        let version = text(&out);
        assert!(
            version.starts_with(&format!("{program} ")),
            "{program} --version: {version}"
        );
    }
}

#[test]
fn the_control_fields_conffile_and_maintainer_scripts() {
    let Some(deb) = package("the_control_fields_conffile_and_maintainer_scripts") else {
        return;
    };
    let field = |name: &str| {
        text(&run(Command::new("dpkg-deb").arg("-f").arg(deb).arg(name)))
            .trim()
            .to_string()
    };
    assert_eq!(field("Package"), "mcm");
    assert_eq!(field("Version"), format!("{}-1", env!("CARGO_PKG_VERSION")));
    let depends = field("Depends");
    assert!(depends.contains("systemd (>= 254)"), "Depends: {depends}");
    assert!(depends.contains("libc6"), "Depends ($auto): {depends}");
    let control = work().join("control");
    let _ = std::fs::remove_dir_all(&control);
    run(Command::new("dpkg-deb").arg("-e").arg(deb).arg(&control));
    let conffiles = std::fs::read_to_string(control.join("conffiles")).unwrap();
    assert_eq!(conffiles.trim(), "/etc/mcm/prob2.toml");
    for script in ["postinst", "prerm", "postrm"] {
        let path = control.join(script);
        let body = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{script}: {e}"));
        let shipped = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("deploy/debian")
            .join(script);
        assert_eq!(body, std::fs::read_to_string(shipped).unwrap(), "{script}");
        run(Command::new("sh").arg("-n").arg(&path));
    }
    let postinst = std::fs::read_to_string(control.join("postinst")).unwrap();
    assert!(postinst.contains("systemd-sysusers mcm.conf"), "{postinst}");
    let code: Vec<&str> = postinst
        .lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect();
    let starting: Vec<&&str> = code
        .iter()
        .filter(|l| !l.trim_start().starts_with("echo"))
        .filter(|l| {
            l.contains("deb-systemd-invoke")
                || l.contains("systemctl")
                    && [" enable", " start", " restart", "--now"]
                        .iter()
                        .any(|w| l.contains(w))
        })
        .collect();
    assert!(
        starting.is_empty(),
        "installing must start and enable nothing: {starting:#?}"
    );
    let postrm = std::fs::read_to_string(control.join("postrm")).unwrap();
    for gone in ["rm -rf /etc/mcm", "userdel mcm"] {
        assert!(postrm.contains(gone), "purge: {gone}: {postrm}");
    }
}

/// systemd-analyze of version 254 or later: the program and the directory of its own units.
struct Analyze {
    program: PathBuf,
    /// `LD_LIBRARY_PATH` for an unpacked one.
    libs: Option<PathBuf>,
    units: PathBuf,
}

fn systemd_version(program: &Path, libs: Option<&Path>) -> Option<u32> {
    let mut cmd = Command::new(program);
    if let Some(l) = libs {
        cmd.env("LD_LIBRARY_PATH", l);
    }
    let out = cmd.arg("--version").output().ok()?;
    text(&out).split_whitespace().nth(1)?.parse().ok()
}

fn systemd_analyze() -> Result<Analyze, String> {
    if let Some(host) = common::find_program("systemd-analyze")
        && systemd_version(&host, None).is_some_and(|v| v >= 254)
    {
        return Ok(Analyze {
            program: host,
            libs: None,
            units: "/usr/lib/systemd/system".into(),
        });
    }
    let dir = work().join("systemd-254");
    let unpacked = dir.join("root");
    let program = unpacked.join("usr/bin/systemd-analyze");
    let libs = unpacked.join("usr/lib/x86_64-linux-gnu/systemd");
    if systemd_version(&program, Some(&libs)).is_none_or(|v| v < 254) {
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&unpacked).unwrap();
        let got = Command::new("apt-get")
            .args([
                "download",
                "systemd/bookworm-backports",
                "libsystemd-shared/bookworm-backports",
            ])
            .current_dir(&dir)
            .output()
            .map_err(|e| format!("no systemd-analyze 254 or later, and no apt-get: {e}"))?;
        if !got.status.success() {
            return Err(format!(
                "no systemd-analyze 254 or later, and `apt-get download systemd/bookworm-backports` \
                 failed (bookworm-backports in the apt sources?): {}",
                String::from_utf8_lossy(&got.stderr)
            ));
        }
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "deb") {
                run(Command::new("dpkg-deb").arg("-x").arg(&path).arg(&unpacked));
            }
        }
    }
    match systemd_version(&program, Some(&libs)) {
        // Debian 12's packages keep the units in /lib (the merged /usr links it).
        Some(v) if v >= 254 => Ok(Analyze {
            program,
            libs: Some(libs),
            units: ["lib/systemd/system", "usr/lib/systemd/system"]
                .map(|d| unpacked.join(d))
                .into_iter()
                .find(|d| d.join("sysinit.target").exists())
                .ok_or_else(|| "no sysinit.target in the unpacked systemd".to_string())?,
        }),
        v => Err(format!(
            "the unpacked systemd-analyze is {v:?}, not 254 or later"
        )),
    }
}

#[test]
fn systemd_analyze_verify_of_every_unit_is_clean() {
    let test = "systemd_analyze_verify_of_every_unit_is_clean";
    let Some(deb) = package(test) else {
        return;
    };
    let analyze = match systemd_analyze() {
        Ok(a) => a,
        Err(why) => return common::skip(test, &why),
    };
    // The package over systemd's own units (sysinit.target, multi-user.target,
    // systemd-networkd.service, ...), as on the robot's computer.
    let root = unpacked(deb, "verify-root");
    run(Command::new("cp")
        .arg("-a")
        .arg(format!("{}/.", analyze.units.display()))
        .arg(root.join("usr/lib/systemd/system")));
    let mut cmd = Command::new(&analyze.program);
    if let Some(libs) = &analyze.libs {
        cmd.env("LD_LIBRARY_PATH", libs);
    }
    cmd.arg("verify")
        .arg(format!("--root={}", root.display()))
        .current_dir(&root)
        .env("SYSTEMD_LOG_LEVEL", "notice");
    for unit in UNITS {
        cmd.arg(format!("usr/lib/systemd/system/{unit}"));
    }
    let out = cmd.output().unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success() && said.trim().is_empty(),
        "systemd-analyze verify ({}): {}\n{said}",
        systemd_version(&analyze.program, analyze.libs.as_deref()).unwrap_or(0),
        out.status
    );
}
