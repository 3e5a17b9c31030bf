#!/bin/bash
# Installs the build into a temporary prefix (nothing is written outside it but CMake's own
# install_manifest.txt in the build folder), moves the prefix to prove it is relocatable, then
# from an unrelated working directory and without SLAMPREP_DATA_DIR:
#   1. `slamprep simulate` (default world and scenario) and one shard of `slamprep bench`
#      (suite by name) find their data beside the moved binary, which does not link OSMesa;
#   2. examples/consumer configures with find_package(slamprep COMPONENTS pipeline) against the
#      moved prefix while pkg-config finds neither Bullet nor OSMesa, builds with the same
#      generator and compiler without naming either (build.ninja, the binary's NEEDED entries),
#      and calibrates the simulated dataset: r_L, r_R and b within 1 % of the truth (the
#      odometry's nominal errors are 2, 1.5 and 4 %), the lidar mount within 2 mm and 0.25 deg
#      (measured: 0.15 mm, 0.57 mm, 0.073 deg).
set -euo pipefail
usage="usage: install_test.sh CMAKE BUILD_DIR SOURCE_DIR GENERATOR CXX_COMPILER [LAUNCHER]"
cmake=${1:?$usage}
build_dir=${2:?$usage}
source_dir=${3:?$usage}
generator=${4:?$usage}
cxx=${5:?$usage}
launcher=${6:-}
unset SLAMPREP_DATA_DIR

dir=$(mktemp -d /tmp/slamprep-install.XXXXXX)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$cmake" --install "$build_dir" --prefix "$dir/staged" >"$dir/install.log" || {
  cat "$dir/install.log"; fail "cmake --install"; }
for f in bin/slamprep lib/cmake/slamprep/slamprepConfig.cmake \
  lib/cmake/slamprep/slamprepConfigVersion.cmake lib/cmake/slamprep/slamprepTargets.cmake \
  include/slamprep/algo/calibration/joint_censi.hpp share/slamprep/worlds/room.yaml \
  share/slamprep/worlds/scenarios/default.yaml share/slamprep/eval/suites/default.yaml; do
  [ -e "$dir/staged/$f" ] || fail "not installed: $f"
done
for lib in core algo sim formats metrics plot pipeline bench; do
  ls "$dir"/staged/lib*/libslamprep_$lib.a >/dev/null 2>&1 || fail "not installed: $lib library"
done
# Only the public headers, each including the project's headers by their prefixed path and only
# installed ones (an INTERNAL header of slamprep_library() is not installed).
for internal in eval/bench/figures_internal.hpp eval/formats/cdr.hpp eval/plot/gl_canvas.hpp; do
  [ ! -e "$dir/staged/include/slamprep/$internal" ] || fail "an internal header installed: $internal"
done
headers=$(cd "$dir/staged/include" && find slamprep -name '*.hpp' | sort)
[ -n "$headers" ] || fail "no headers installed"
for header in $headers; do
  while read -r included; do
    [ -e "$dir/staged/include/$included" ] || fail "$header includes $included, not installed"
  done < <(sed -n 's/^#include "\(slamprep\/[^"]*\)".*/\1/p' "$dir/staged/include/$header")
  if grep -nE '^#include "(core|algo|sim|eval|app)/' "$dir/staged/include/$header"; then
    fail "$header includes a project header without the slamprep/ prefix"
  fi
done
echo "ok: $(echo "$headers" | wc -l) public headers, every included one installed"
mv "$dir/staged" "$dir/prefix"
prefix=$dir/prefix

# 1. The moved binary, run from a folder that holds no data.
mkdir "$dir/work" && cd "$dir/work"
"$prefix/bin/slamprep" simulate --out "$dir/ds" >"$dir/simulate.log" 2>&1 || {
  tail -20 "$dir/simulate.log"; fail "slamprep simulate from the moved prefix"; }
"$prefix/bin/slamprep" bench --suite default --shard 2/3 --no-plots --quiet \
  --results "$dir/results" >"$dir/bench.log" 2>&1 || {
  tail -20 "$dir/bench.log"; fail "slamprep bench --shard 2/3 from the moved prefix"; }
[ -d "$dir/results/default/shards/2-of-3" ] || fail "bench wrote no shard"
echo "ok: the moved binary finds worlds, scenarios and suites"
# OSMesa (and the libLLVM behind it) is loaded at the first plot, not at every start.
if readelf -d "$prefix/bin/slamprep" | grep -i 'NEEDED.*\(osmesa\|llvm\)'; then
  fail "slamprep links OSMesa; plot loads it at the first render (eval/plot/osmesa_library.cpp)"
fi

# 2. The consumer project against the moved prefix, on a machine as if it had neither Bullet nor
# OSMesa: pkg-config sees every module but those.
hidden=$dir/pkgconfig
mkdir "$hidden"
search=${PKG_CONFIG_PATH:+$PKG_CONFIG_PATH:}$(pkg-config --variable pc_path pkg-config)
for d in ${search//:/ }; do
  for f in "$d"/*.pc; do
    case ${f##*/} in
      bullet*.pc | osmesa.pc | '*.pc') ;;
      *) [ -e "$hidden/${f##*/}" ] || ln -s "$f" "$hidden/" ;;
    esac
  done
done
for module in bullet-float64 osmesa; do
  ! PKG_CONFIG_LIBDIR=$hidden PKG_CONFIG_PATH= pkg-config --exists $module ||
    fail "could not hide $module from pkg-config"
done
consumer=(-S "$source_dir/examples/consumer" -B "$dir/consumer" -G "$generator"
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx")
[ -n "$launcher" ] && consumer+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$launcher")
PKG_CONFIG_LIBDIR=$hidden PKG_CONFIG_PATH= "$cmake" "${consumer[@]}" >"$dir/consumer.log" 2>&1 || {
  tail -30 "$dir/consumer.log"; fail "configuring examples/consumer without Bullet and OSMesa"; }
found=$(sed -n 's/^slamprep_DIR:PATH=//p' "$dir/consumer/CMakeCache.txt")
[ "$found" = "$prefix/lib/cmake/slamprep" ] ||
  [ "$found" = "$prefix/lib64/cmake/slamprep" ] || fail "found slamprep in '$found', not $prefix"
"$cmake" --build "$dir/consumer" >>"$dir/consumer.log" 2>&1 || {
  tail -30 "$dir/consumer.log"; fail "building examples/consumer"; }
if grep -q "warning:" "$dir/consumer.log"; then
  grep -A3 "warning:" "$dir/consumer.log"; fail "examples/consumer builds with warnings"
fi
if grep -sil 'bullet\|osmesa' "$dir/consumer/build.ninja" "$dir/consumer/CMakeCache.txt"; then
  fail "examples/consumer names Bullet or OSMesa in its build"
fi
if readelf -d "$dir/consumer/calibrate_dataset" | grep -i 'NEEDED.*\(bullet\|osmesa\)'; then
  fail "calibrate_dataset links Bullet or OSMesa"
fi
echo "ok: examples/consumer builds with neither Bullet nor OSMesa"
"$dir/consumer/calibrate_dataset" "$dir/ds" | tee "$dir/calibration.txt" ||
  fail "calibrate_dataset exited non-zero"

# name estimate truth -> |estimate - truth| against a relative or absolute tolerance.
check() {
  local name=$1 kind=$2 tolerance=$3
  awk -v name="$name" -v kind="$kind" -v tol="$tolerance" '
    $1 == name { seen = 1; e = $2 - $3; if (e < 0) e = -e
                 if (kind == "rel") e /= ($3 < 0 ? -$3 : $3)
                 ok = e <= tol; printf "%s error %.3g (tolerance %s %s)\n", name, e, kind, tol }
    END { exit !(seen && ok) }' "$dir/calibration.txt" || fail "$name outside tolerance"
}
check r_L_m rel 0.01
check r_R_m rel 0.01
check b_m rel 0.01
check lidar_x_m abs 0.002
check lidar_y_m abs 0.002
check lidar_yaw_rad abs 0.0044  # 0.25 deg
echo "ok: examples/consumer calibrates the dataset through the installed package"
