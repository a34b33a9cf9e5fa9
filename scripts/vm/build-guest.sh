#!/usr/bin/env bash
# Builds the test guest of tests/vm/ (tests/common/vm.rs boots it with QEMU): a Debian
# root file system made with debootstrap from Debian's package registry, with Debian's stock
# kernel (it has SocketCAN: can, can-raw, can-dev, vcan), systemd as PID 1, vcan0 up at boot,
# can-utils, python3 with python-can, and the agent that runs the host's commands
# (scripts/vm/rootfs/ is copied over the file system as it is).
#
# Output, in the cache directory $MCM_VM_CACHE (default ~/.cache/mcm/vm, or
# $XDG_CACHE_HOME/mcm/vm), as guest-KEY/: vmlinuz, initrd.img (both from the guest's /boot, the
# initrd made by Debian's package in the chroot), rootfs.img (raw ext4, made without mounting:
# mkfs.ext4 -d) and build-info.txt (time, sizes). KEY is a hash of this script, rootfs/, the
# suite and the package list: an edit of any of them builds a new guest; otherwise a rerun only
# prints the directory. The last line printed on stdout is always that directory. The cache is
# outside the work tree, so that a new clone or `cargo clean` does not build the guest again
# (a minute and a half on an idle 2-core machine, up to five under load); guests of other keys
# not used for a week are removed. The .deb files are kept in debs/ there for the next build.
#
# Needs root (debootstrap, and files owned by root in the image), debootstrap, mkfs.ext4 and the
# network to Debian's registry. Boot by hand: docs/testing.md ("The virtual machine").
#
# Environment: MCM_VM_SUITE (default trixie: systemd >= 254 for the MCM's units), MCM_VM_MIRROR
# (default http://deb.debian.org/debian).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
suite=${MCM_VM_SUITE:-trixie}
mirror=${MCM_VM_MIRROR:-http://deb.debian.org/debian}
# dbus: systemctl, systemd-run and the like speak to systemd over it (without it they say
# they cannot connect, then fall back to systemd's private socket).
packages=(linux-image-amd64 systemd-sysv udev dbus kmod iproute2 can-utils python3 python3-can
    procps)
# Free space left in the image for the tests (installing a package, logs), MiB.
free_mib=768

log() { echo "build-guest: $*" >&2; }

key=$(
    {
        cat "$0"
        (cd "$here" && find rootfs -type f -o -type l | LC_ALL=C sort | while read -r f; do
            echo "== $f $(stat -c %a "$f")"
            cat "$f"
        done)
        echo "$suite $mirror ${packages[*]}"
    } | sha256sum | cut -c1-16
)
vm=${MCM_VM_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/mcm/vm}
out=$vm/guest-$key
mkdir -p "$vm"

# One build at a time (tests running in parallel all ask for the guest).
exec 9>"$vm/build.lock"
flock 9

if [ -f "$out/build-info.txt" ]; then
    # Used now: its age below counts from here.
    touch "$out/build-info.txt"
    echo "$out"
    exit 0
fi

missing=()
[ "$(id -u)" -eq 0 ] || missing+=("root (debootstrap needs it)")
command -v debootstrap >/dev/null 2>&1 || missing+=(debootstrap)
command -v mkfs.ext4 >/dev/null 2>&1 || missing+=("mkfs.ext4 (e2fsprogs)")
if [ "${#missing[@]}" -gt 0 ]; then
    log "cannot build the guest: missing ${missing[*]} (.ci/run installs them)"
    exit 2
fi

work=$vm/build-$key
root=$work/root
# debootstrap mounts /proc and /sys (and maybe more) inside the root: unmount all of it before
# removing anything, and never cross into another file system.
cleanup() {
    if [ -d "$work" ]; then
        findmnt -rno TARGET | grep -F "$work/" | sort -r | while read -r m; do
            umount -l "$m" || true
        done
        rm -rf --one-file-system "$work"
    fi
}
trap cleanup EXIT
cleanup
mkdir -p "$work" "$vm/debs"

started=$(date +%s)
log "debootstrap $suite (${packages[*]}) into $root; log: $work/debootstrap.log"
packs=$(
    IFS=,
    echo "${packages[*]}"
)
if ! debootstrap --variant=minbase --cache-dir="$vm/debs" --include="$packs" \
    "$suite" "$root" "$mirror" >"$work/debootstrap.log" 2>&1; then
    tail -n 30 "$work/debootstrap.log" >&2
    cp "$work/debootstrap.log" "$vm/debootstrap-failed.log" || true
    log "debootstrap failed (the whole log: $vm/debootstrap-failed.log)"
    exit 1
fi
bootstrapped=$(date +%s)

log "configuring the guest"
cp -R --no-preserve=ownership "$here/rootfs/." "$root/"
echo mcm-guest >"$root/etc/hostname"
printf '127.0.0.1 localhost\n127.0.1.1 mcm-guest\n::1 localhost\n' >"$root/etc/hosts"
# A fixed machine id: an empty one would make every boot of an overlay a "first boot".
tr -d '-' </proc/sys/kernel/random/uuid >"$root/etc/machine-id"
# Root logs in on the serial console without a password: a test guest only.
chroot "$root" passwd -d root >/dev/null
chroot "$root" systemctl enable --quiet systemd-networkd.service \
    systemd-networkd-wait-online.service mcm-guest-agent.service mcm-guest-cpus.service
# Timers that would only load the guest (no network to update from anyway).
chroot "$root" systemctl mask --quiet apt-daily.timer apt-daily-upgrade.timer \
    dpkg-db-backup.timer fstrim.timer e2scrub_all.timer
# The mount points of the shares.
mkdir -p "$root/mnt/mcm-ro" "$root/mnt/mcm-rw"

kernel=$(find "$root/boot" -maxdepth 1 -name 'vmlinuz-*' | sort | tail -n 1)
initrd=$(find "$root/boot" -maxdepth 1 -name 'initrd.img-*' | sort | tail -n 1)
if [ -z "$kernel" ] || [ -z "$initrd" ]; then
    log "no kernel or initrd in $root/boot: $(ls "$root/boot")"
    exit 1
fi
cp "$kernel" "$work/vmlinuz"
cp "$initrd" "$work/initrd.img"
release=${kernel##*/vmlinuz-}
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko \
    drivers/net/can/vcan.ko; do
    if ! ls "$root/lib/modules/$release/kernel/$m"* >/dev/null 2>&1; then
        log "the kernel $release has no $m"
        exit 1
    fi
done

# What the guest does not need at run time: package caches and lists, documentation.
rm -rf "$root"/var/cache/apt/archives/*.deb "$root"/var/cache/apt/*.bin \
    "$root"/var/lib/apt/lists/* "$root"/usr/share/doc/* "$root"/usr/share/man/* \
    "$root"/usr/share/info/* "$root"/boot/initrd.img-*

used_mib=$(du -sxm "$root" | cut -f1)
size_mib=$((used_mib * 11 / 10 + free_mib))
log "making the ext4 image ($size_mib MiB for $used_mib MiB of files)"
mkfs.ext4 -q -F -L mcm-guest -d "$root" "$work/rootfs.img" "${size_mib}M"
rm -rf --one-file-system "$root"
finished=$(date +%s)

{
    echo "suite: $suite"
    echo "kernel: $release"
    echo "packages: ${packages[*]}"
    echo "built: $(date -u +%FT%TZ) on $(hostname)"
    echo "debootstrap: $((bootstrapped - started)) s"
    echo "total: $((finished - started)) s"
    echo "files: $used_mib MiB"
    echo "image: $size_mib MiB ($(du -m "$work/rootfs.img" | cut -f1) MiB on disk, sparse)"
    echo "kernel + initrd: $(du -cm "$work/vmlinuz" "$work/initrd.img" | tail -n 1 | cut -f1) MiB"
} >"$work/info.tmp"

mv "$work/info.tmp" "$work/build-info.txt"
rm -rf "$out"
mv "$work" "$out"
# Guests of other keys (other versions of this script or rootfs/, maybe another checkout's) not
# used for a week.
find "$vm" -mindepth 2 -maxdepth 2 -path "$vm/guest-*/build-info.txt" -mtime +7 \
    ! -path "$out/*" -printf '%h\0' | xargs -0 -r rm -rf
log "built in $((finished - started)) s: $out"
sed 's/^/build-guest:   /' "$out/build-info.txt" >&2
echo "$out"
