#!/usr/bin/env bash
# Prism's fastest binary: a profile-guided build (PGO) of `prism`, written to target/pgo/prism.
#
#   benches/pgo/build.sh            # about 4 minutes on 2 cores: two release builds and a 20-second training run
#   benches/pgo/build.sh --if-available   # (CI) exit 0 with a message when llvm-profdata cannot be had (no rustup,
#                                         # no network); a difference between the two builds' images still fails
#
# 1. Builds `prism` instrumented (`-Cprofile-generate`) into target/pgo/generate.
# 2. Trains it on the repository's scenes with every integrator and accelerator at a small size: `envlight`,
#    `phong` and `ppm` renders, and `prism bench` with all four accelerators. The three boxes the speed comparison
#    with Mitsuba measures (cornell_box, cornell_rough, cornell_caustic) and cornell_direct, which shares their
#    geometry, are left out, so the gains measured on them are on scenes the profile has not seen.
# 3. Merges the profile with the toolchain's `llvm-profdata` (`rustup component add llvm-tools` if it is missing:
#    the one install this needs beyond the toolchain) and builds `prism` again with `-Cprofile-use` into
#    target/pgo/use, copied to target/pgo/prism.
# 4. Checks that the binary renders exactly what the plain release build renders: the Cornell box (small) and a
#    `ppm` render, compared byte for byte with `target/release/prism`'s (built if missing). PGO changes which code
#    is laid out where and what is inlined, never the floating-point operations, so the images must match.
#
# The default build stays the plain one (the profile-guided binary measured slower than it:
# docs/decisions/0018-pgo-not-default.md); this script remains for measuring, and CI checks that its images match.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
OUT=$ROOT/target/pgo
DATA=$OUT/profiles
mkdir -p "$OUT"
# The record of which sources the binary was built from (written by benches/peer/mitsuba_compare.py after a build it
# asked for) no longer holds once this script builds.
rm -f "$OUT/prism.sources-sha256"

sysroot=$(rustc --print sysroot)
host=$(rustc -vV | sed -n 's/^host: //p')
profdata=$sysroot/lib/rustlib/$host/bin/llvm-profdata
if [ ! -x "$profdata" ]; then
    echo "pgo: installing llvm-tools (llvm-profdata) with rustup ..." >&2
    rustup component add llvm-tools >&2 || true
fi
if [ ! -x "$profdata" ]; then
    if [ "${1:-}" = "--if-available" ]; then
        echo "pgo: skipped: no llvm-profdata at $profdata (rustup component add llvm-tools failed)" >&2
        exit 0
    fi
    echo "pgo: error: no llvm-profdata at $profdata (install it with: rustup component add llvm-tools)" >&2
    exit 1
fi

echo "pgo: building the instrumented binary ..." >&2
rm -rf "$DATA"
RUSTFLAGS="${RUSTFLAGS:-} -Cprofile-generate=$DATA" \
    cargo build --release --quiet --bin prism --target-dir "$OUT/generate"
gen=$OUT/generate/release/prism

echo "pgo: training ..." >&2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
train() { "$gen" "$@" -q -o "$work/train.exr" > /dev/null; }
for scene in dof env_sphere furnace nested textured textured_box vase_teapot vase_teapot_env; do
    train render "scenes/$scene.ron" --size 96x96 --spp 16 --threads 2
done
train render scenes/textured.ron --size 96x96 --spp 16 --threads 2 --adaptive
train render scenes/dof.ron --size 96x96 --spp 8 --threads 2 --integrator ppm
train render scenes/textured.ron --size 96x96 --spp 8 --threads 2 --integrator ppm
train render scenes/vase_teapot_env.ron --size 64x64 --spp 4 --threads 2 --accel kdtree
train render scenes/vase_teapot_env.ron --size 64x64 --spp 4 --threads 2 --accel grid
"$gen" bench scenes/report/teapot_in_stadium.ron --accel all --size 64 --seconds 0.1 > /dev/null 2> "$work/bench.log" \
    || { cat "$work/bench.log" >&2; exit 1; }

"$profdata" merge -o "$OUT/prism.profdata" "$DATA"

echo "pgo: building with the profile ..." >&2
RUSTFLAGS="${RUSTFLAGS:-} -Cprofile-use=$OUT/prism.profdata" \
    cargo build --release --quiet --bin prism --target-dir "$OUT/use"
cp "$OUT/use/release/prism" "$OUT/prism"

echo "pgo: checking its images against the plain release build ..." >&2
cargo build --release --quiet --bin prism
for args in "scenes/cornell_box.ron --spp 16" "scenes/cornell_caustic.ron --spp 4 --integrator ppm"; do
    # shellcheck disable=SC2086 # the arguments are meant to split
    target/release/prism render $args --size 64x64 --threads 2 -q -o "$work/plain.exr"
    # shellcheck disable=SC2086
    "$OUT/prism" render $args --size 64x64 --threads 2 -q -o "$work/pgo.exr"
    if ! cmp -s "$work/plain.exr" "$work/pgo.exr"; then
        echo "pgo: error: the PGO binary's image of '$args' differs from the plain build's" >&2
        exit 1
    fi
done
echo "$OUT/prism"
