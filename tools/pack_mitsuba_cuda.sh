#!/usr/bin/env bash
# Packs Mitsuba 3's cuda_ad_rgb variant for a GPU machine that cannot reach
# a package index: the cp312 manylinux wheels of mitsuba
# and drjit, less the other variants, include/, the spectral data and every
# plugin neither the peer scenes nor scenes/mitsuba/ load (the full wheel is over a 64 MiB
# carry limit; this is about 16 MB).
#
#   tools/pack_mitsuba_cuda.sh OUT.tar.xz [MITSUBA_VERSION] [DRJIT_VERSION]
#
# On the GPU machine: mkdir /tmp/mi && tar xJf OUT.tar.xz -C /tmp/mi &&
# export PYTHONPATH=/tmp/mi (its python3 must be 3.12 and have numpy).
set -euo pipefail
OUT=$(realpath "$1"); MI=${2:-3.9.1}; DJ=${3:-1.5.0}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
for p in mitsuba==$MI drjit==$DJ; do
  python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 \
    --implementation cp --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 \
    -d "$T/whl" "$p"
done
mkdir "$T/pkg" && cd "$T/pkg"
for w in "$T"/whl/*.whl; do unzip -q -o "$w"; done
KEEP="volpath perspective hdrfilm independent box cube null heterogeneous homogeneous
  gridvolume constvolume hg isotropic constant point srgb uniform rectangle diffuse d65
  regular bitmap merge shapegroup instance rawconstant mask direct path sphere obj ply
  serialized tent gaussian area envmap twosided dielectric thindielectric roughdielectric
  plastic roughplastic conductor roughconductor checkerboard directional spot volpathmis
  moment disk"
mkdir keep && for p in $KEEP; do cp "mitsuba/plugins/$p.so" keep/; done
rm -rf mitsuba/plugins && mv keep mitsuba/plugins
rm -rf mitsuba/include mitsuba/cmake mitsuba/data/srgb.coeff mitsuba/data/sunsky \
  mitsuba/*llvm_ad* mitsuba/cuda_ad_mono* mitsuba/cuda_ad_spectral* mitsuba/scalar_* \
  drjit/include drjit/cmake
tar cJf "$OUT" mitsuba drjit
ls -la "$OUT"
