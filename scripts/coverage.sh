#!/usr/bin/env bash
# Line coverage of the workspace's crates, measured by their own tests, printed as a markdown
# table (one row per crate) ready to paste into docs/testing.md.
#
#   scripts/coverage.sh            # every member crate's unit, property and tests/ tests
#   scripts/coverage.sh --e2e      # also the root package's end-to-end tests (tests/)
#   scripts/coverage.sh --html     # also an HTML report, in $CARGO_TARGET_DIR/llvm-cov/html
#   scripts/coverage.sh --doctests # also the doc tests (needs a nightly toolchain)
#
# Tool: cargo-llvm-cov (rustc's `-C instrument-coverage`), with `llvm-profdata` and `llvm-cov`
# from Debian's llvm package: rustup cannot download `llvm-tools-preview` on our machines. Both
# are installed here when missing (apt-get needs root). Debian's LLVM must read the profiles
# of rustc's LLVM: LLVM 19 reads those of rustc 1.95 (LLVM 22); LLVM 14 does not.
#
# Output: the crate table on stdout; every file's figure in $CARGO_TARGET_DIR/coverage/files.md,
# least covered first. Test code is not counted: files under tests/, benches/ and examples/,
# and test modules kept in their own file (`tests.rs`, `*_tests.rs`). Inline `mod tests`
# blocks cannot be excluded on a stable toolchain and count as covered source.
set -euo pipefail
cd "$(dirname "$0")/.."

LLVM_COV_VERSION=0.9.1 # cargo-llvm-cov, pinned so that a fresh machine measures the same way
DEBIAN_LLVM=19         # the newest LLVM in Debian bookworm
IGNORE='(^|/)(tests|benches|examples)/|(^|/)([A-Za-z0-9_]+_)?tests\.rs$'

e2e=0 html=0 doctests=0
for arg in "$@"; do
    case "$arg" in
        --e2e) e2e=1 ;;
        --html) html=1 ;;
        --doctests) doctests=1 ;;
        -h | --help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "coverage.sh: unknown argument \`$arg\` (allowed: --e2e, --html, --doctests)" >&2; exit 2 ;;
    esac
done

# --- the tools -----------------------------------------------------------------------------
# LLVM: $LLVM_PROFDATA and $LLVM_COV if set, else the newest /usr/lib/llvm-N (N >= 19), else
# Debian's llvm-$DEBIAN_LLVM installed with apt-get.
find_llvm() {
    local n
    for n in 22 21 20 19; do
        if [ -x "/usr/lib/llvm-$n/bin/llvm-profdata" ] && [ -x "/usr/lib/llvm-$n/bin/llvm-cov" ]; then
            echo "/usr/lib/llvm-$n/bin"
            return 0
        fi
    done
    return 1
}
if [ -z "${LLVM_PROFDATA:-}" ] || [ -z "${LLVM_COV:-}" ]; then
    if ! llvm_bin=$(find_llvm); then
        if [ "$EUID" -ne 0 ] || ! command -v apt-get >/dev/null 2>&1; then
            echo "coverage.sh: no LLVM >= 19 under /usr/lib/llvm-*; install llvm-$DEBIAN_LLVM" \
                "(apt-get, as root) or set LLVM_PROFDATA and LLVM_COV" >&2
            exit 1
        fi
        echo "coverage.sh: installing llvm-$DEBIAN_LLVM with apt-get" >&2
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "llvm-$DEBIAN_LLVM" >/dev/null
        llvm_bin=$(find_llvm)
    fi
    export LLVM_PROFDATA="$llvm_bin/llvm-profdata" LLVM_COV="$llvm_bin/llvm-cov"
fi

if [ "$(cargo llvm-cov --version 2>/dev/null)" != "cargo-llvm-cov $LLVM_COV_VERSION" ]; then
    echo "coverage.sh: installing cargo-llvm-cov $LLVM_COV_VERSION with cargo install" >&2
    cargo install cargo-llvm-cov --locked --version "$LLVM_COV_VERSION"
fi

# --- the run -------------------------------------------------------------------------------
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
out="$CARGO_TARGET_DIR/coverage"
mkdir -p "$out"
# The crates are the workspace's members, as cargo lists them; the root package (if any) is
# the one whose manifest is the workspace's.
cargo metadata --no-deps --format-version 1 >"$out/metadata.json"
root_pkg=$(python3 -c 'import json, sys
m = json.load(open(sys.argv[1]))
print(next((p["name"] for p in m["packages"] if p["manifest_path"] == m["workspace_root"] + "/Cargo.toml"), ""))' "$out/metadata.json")

toolchain=() test_args=()
if [ "$doctests" = 1 ]; then
    toolchain=(+nightly)
    test_args+=(--doctests)
fi

# Instrumented code takes more stack than the dev profile's: a controller test that runs the
# whole robot on the test thread overflows the default 2 MiB there.
export RUST_MIN_STACK="${RUST_MIN_STACK:-16777216}"
# Old profiles would be merged into this run's (`--no-report` keeps them): remove them, and the
# workspace's old instrumented artifacts with them.
cargo "${toolchain[@]}" llvm-cov clean --workspace
start=$(date +%s)
if [ "$e2e" = 1 ] || [ -z "$root_pkg" ]; then
    cargo "${toolchain[@]}" llvm-cov --no-report --workspace "${test_args[@]}"
else
    # Every member but the root package, whose tests/ start the real processes in real time.
    cargo "${toolchain[@]}" llvm-cov --no-report --workspace --exclude "$root_pkg" "${test_args[@]}"
fi
echo "coverage.sh: tests ran in $(($(date +%s) - start)) s" >&2

# `--workspace`: without it the report keeps only the root package's files.
report=(--workspace --ignore-filename-regex "$IGNORE")
cargo "${toolchain[@]}" llvm-cov report --json --summary-only --output-path "$out/summary.json" "${report[@]}"
if [ "$html" = 1 ]; then
    cargo "${toolchain[@]}" llvm-cov report --html "${report[@]}"
    echo "coverage.sh: HTML report in $CARGO_TARGET_DIR/llvm-cov/html/index.html" >&2
fi

# --- the tables ----------------------------------------------------------------------------
# Each file belongs to the crate whose directory is the longest prefix of its path.
python3 - "$out/metadata.json" "$out/summary.json" "$out/files.md" "$e2e" "$root_pkg" <<'PY'
import json, os, sys

meta_path, summary_path, files_path, e2e, root_pkg = sys.argv[1:]
e2e = e2e == "1"
meta = json.load(open(meta_path))
root = meta["workspace_root"]
crates = sorted(
    ((os.path.dirname(p["manifest_path"]) + "/", p["name"]) for p in meta["packages"]),
    key=lambda c: -len(c[0]),
)
totals = {name: [0, 0] for _, name in crates}
files = []
for f in json.load(open(summary_path))["data"][0]["files"]:
    owner = next((name for d, name in crates if f["filename"].startswith(d)), None)
    if owner is None:
        continue
    lines = f["summary"]["lines"]
    totals[owner][0] += lines["covered"]
    totals[owner][1] += lines["count"]
    files.append((owner, os.path.relpath(f["filename"], root), lines["covered"], lines["count"]))

def pct(covered, count):
    return f"{100.0 * covered / count:.1f} %" if count else "-"

print("| crate | lines covered / total | line coverage |")
print("| --- | ---: | ---: |")
for name in sorted(totals):
    covered, count = totals[name]
    if name == root_pkg and not e2e:
        print(f"| `{name}` | (end-to-end tests not run: `--e2e`) | - |")
    else:
        print(f"| `{name}` | {covered} / {count} | {pct(covered, count)} |")
all_cov = sum(c for n, (c, _) in totals.items() if e2e or n != root_pkg)
all_cnt = sum(t for n, (_, t) in totals.items() if e2e or n != root_pkg)
print(f"| all | {all_cov} / {all_cnt} | {pct(all_cov, all_cnt)} |")

files.sort(key=lambda f: (f[2] / f[3] if f[3] else 1.0, -f[3]))
with open(files_path, "w") as out:
    out.write("| crate | file | lines covered / total | line coverage |\n| --- | --- | ---: | ---: |\n")
    for owner, name, covered, count in files:
        out.write(f"| `{owner}` | `{name}` | {covered} / {count} | {pct(covered, count)} |\n")
print(f"\nEvery file, least covered first: {files_path}", file=sys.stderr)
PY
