#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Install checks of SmoothForce (tests/install/CMakeLists.txt runs them under ctest):
#   check_install.sh install   BUILD_DIR PREFIX          cmake --install into a fresh PREFIX, check the tree
#   check_install.sh cmake     PREFIX CONSUMER_DIR WORK MESH   find_package consumer: configure, build, run
#   check_install.sh pkgconfig PREFIX MAIN_CPP WORK MESH       one-file program built with pkg-config, run
#   check_install.sh headers   PREFIX WORK                installed headers: alone (preprocessor), together (compiler)
#   check_install.sh plots     PREFIX WORK MESH           the installed smoothforce finds its plot script (share/)
#   check_install.sh capi      PREFIX EXAMPLE_C WORK MESH  the C example compiled as C99 against <smoothforce.h>, run
#   check_install.sh python    PREFIX EXAMPLE_PY MESH     the Python example against the installed module
# Environment (set by CMake): SF_CXX, SF_CMAKE, SF_GENERATOR, SF_SHARED_LIBS (1/0),
# SF_HAS_OPENCL (1/0), SF_VERSION. Prints what it checked; exit status 1 on the first failure.
set -euo pipefail

fail() {
  echo "check_install: FAILED: $*" >&2
  exit 1
}
cxx=${SF_CXX:-c++}
cmake=${SF_CMAKE:-cmake}

libdir_of() {  # the folder holding lib/.../cmake/SmoothForce
  local cfg
  cfg=$(find "$1" -name SmoothForceConfig.cmake -path '*/cmake/SmoothForce/*' | head -n1)
  [[ -n $cfg ]] || fail "no SmoothForceConfig.cmake under $1"
  dirname "$(dirname "$(dirname "$cfg")")"
}

check_consumer_output() {  # $1: output file
  local out=$1
  cat "$out"
  grep -q "^SmoothForce $SF_VERSION " "$out" || fail "consumer did not print version $SF_VERSION"
  grep -q "^mesh: 180 faces, 188 vertices$" "$out" || fail "consumer did not read the 180-face spot cage"
  grep -q "^force steps: 4 in contact of 6$" "$out" || fail "consumer: expected 4 of 6 steps in contact"
  grep -q "^consumer: OK$" "$out" || fail "consumer did not report OK"
}

cmd=${1:-}
shift || true
case $cmd in
  install)
    build=$1 prefix=$2
    rm -rf "$prefix"
    "$cmake" --install "$build" --prefix "$prefix" >/dev/null
    lib=$(libdir_of "$prefix")
    for f in "$lib/cmake/SmoothForce/SmoothForceConfig.cmake" "$lib/cmake/SmoothForce/SmoothForceConfigVersion.cmake" \
      "$lib/cmake/SmoothForce/SmoothForceTargets.cmake" "$lib/pkgconfig/smoothforce.pc" \
      "$prefix/include/smoothforce/smoothforce.h" "$prefix/include/smoothforce/version.h" \
      "$prefix/include/smoothforce/config.h" "$prefix/bin/smoothforce" "$prefix/share/smoothforce/sweep_plots.py"; do
      [[ -f $f ]] || fail "missing $f"
    done
    for m in base mesh patch query force opencl sweep runtime; do
      if [[ $SF_SHARED_LIBS == 1 ]]; then
        so=$lib/libsmoothforce_$m.so
        [[ -L $so ]] || fail "missing $so"
        soname=$(readelf -d "$so" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
        [[ $soname == libsmoothforce_$m.so.${SF_VERSION%.*} ]] || fail "$so: SONAME '$soname'"
        [[ -f $lib/libsmoothforce_$m.so.$SF_VERSION ]] || fail "missing $lib/libsmoothforce_$m.so.$SF_VERSION"
      else
        [[ -f $lib/libsmoothforce_$m.a ]] || fail "missing $lib/libsmoothforce_$m.a"
      fi
    done
    # Private and in-tree-only headers stay out: detail/, mesh_io_detail.h, surface_tessellation.h,
    # opencl_program.h, patch_simd_detail.h, kernels/ and gp_lanes-inl.h.
    bad=$(find "$prefix/include" \( -name detail -o -name 'mesh_io_detail.h' -o -name 'surface_tessellation.h' \
      -o -name 'opencl_program.h' -o -name 'patch_simd_detail.h' \
      -o -name 'gp_*.h' -o -name '*.cl' -o -name 'sf_kernel_sources.h' \) -print)
    [[ -z $bad ]] || fail "private headers installed: $bad"
    if [[ $SF_HAS_OPENCL == 0 && -e $prefix/include/smoothforce/opencl/opencl_context.h ]]; then
      fail "CPU-only build installed opencl_context.h"
    fi
    "$prefix/bin/smoothforce" --version | grep -q "^smoothforce $SF_VERSION" || fail "installed CLI --version"
    echo "installed into $prefix: $(find "$prefix" -type f | wc -l) files, libraries in $lib"
    ;;
  cmake)
    prefix=$1 src=$2 work=$3 mesh=$4
    rm -rf "$work"
    "$cmake" -S "$src" -B "$work" -G "$SF_GENERATOR" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
      -DCMAKE_PREFIX_PATH="$prefix" >"$work.configure.log" 2>&1 || { cat "$work.configure.log"; fail "configure"; }
    grep "SmoothForce $SF_VERSION from $prefix" "$work.configure.log" || fail "found a SmoothForce other than $prefix"
    "$cmake" --build "$work" >"$work.build.log" 2>&1 || { cat "$work.build.log"; fail "build"; }
    "$work/consumer" "$mesh" >"$work.out" || { cat "$work.out"; fail "consumer exited with $?"; }
    check_consumer_output "$work.out"
    ;;
  pkgconfig)
    prefix=$(cd "$1" && pwd) main=$2 work=$3 mesh=$4
    lib=$(libdir_of "$prefix")
    rm -rf "$work" && mkdir -p "$work"
    export PKG_CONFIG_PATH=$lib/pkgconfig
    static=()
    [[ $SF_SHARED_LIBS == 1 ]] || static=(--static)
    [[ $(pkg-config --modversion smoothforce) == "$SF_VERSION" ]] || fail "pkg-config --modversion"
    # shellcheck disable=SC2046
    flags=$(pkg-config "${static[@]}" --cflags --libs smoothforce)
    echo "$cxx $main $flags"
    # shellcheck disable=SC2086
    "$cxx" "$main" $flags -o "$work/consumer" || fail "compile and link with pkg-config"
    LD_LIBRARY_PATH=$lib "$work/consumer" "$mesh" >"$work/out" || { cat "$work/out"; fail "consumer exited with $?"; }
    check_consumer_output "$work/out"
    ;;
  headers)
    # Every installed header alone through the preprocessor with only the installed tree on the
    # include path (a private or kernels/ include fails), and all of them in one translation
    # unit through the compiler. SF_HEADERS_ALONE=1 compiles each one alone as well
    # (self-contained headers; about 1.5 s of CPU per header that pulls in Eigen).
    prefix=$(cd "$1" && pwd) work=$2
    lib=$(libdir_of "$prefix")
    rm -rf "$work" && mkdir -p "$work"
    flags=$(PKG_CONFIG_PATH=$lib/pkgconfig pkg-config --cflags smoothforce)
    headers=$(cd "$prefix/include" && find smoothforce -name '*.h' | sort)
    n=0
    for h in $headers; do
      echo "#include <$h>" >"$work/$(echo "$h" | tr / _).cpp"
      echo "#include <$h>" >>"$work/all_headers.cpp"
      n=$((n + 1))
    done
    mode=-E
    [[ ${SF_HEADERS_ALONE:-0} == 1 ]] && mode=-fsyntax-only
    # shellcheck disable=SC2016
    (cd "$work" && ls ./*.h.cpp | xargs -P "$(nproc)" -I{} sh -c '"$0" $1 $2 -o /dev/null {} >{}.log 2>&1 || { echo "FAILED: {}"; cat {}.log; }' \
      "$cxx" "$mode" "$flags") | tee "$work/failures.log"
    [[ ! -s $work/failures.log ]] || fail "installed headers that do not $([[ $mode == -E ]] && echo preprocess || echo compile) alone"
    echo "$n installed headers $([[ $mode == -E ]] && echo preprocess || echo compile) alone"
    # shellcheck disable=SC2086
    "$cxx" -fsyntax-only -Wall -Wextra $flags "$work/all_headers.cpp" || fail "the installed headers do not compile together"
    echo "all $n compile together (-Wall -Wextra: no warning)"
    # The umbrella names every core header (base .. force, opencl), except the CL bindings.
    missing=""
    for h in $headers; do
      case $h in
        smoothforce/base/* | smoothforce/mesh/* | smoothforce/patch/* | smoothforce/query/* | smoothforce/force/* | \
          smoothforce/opencl/*)
          [[ $h == smoothforce/opencl/opencl_context.h ]] && continue
          grep -q "^#include <$h>" "$prefix/include/smoothforce/smoothforce.h" || missing+=" $h"
          ;;
      esac
    done
    [[ -z $missing ]] || fail "smoothforce.h does not include:$missing"
    echo "smoothforce.h includes every core header"
    ;;
  plots)
    # A sweep by the installed binary, with no SF_SWEEP_PLOTS: the script must come from
    # PREFIX/share/smoothforce (the binary looks next to itself; the source tree is only for the
    # binary of the build tree), and every PNG gets its PDF.
    prefix=$(cd "$1" && pwd) work=$2 mesh=$3
    rm -rf "$work" && mkdir -p "$work"
    /usr/bin/python3 -c 'import matplotlib' 2>/dev/null || fail "no /usr/bin/python3 with matplotlib (tools/setup)"
    env -u SF_SWEEP_PLOTS "$prefix/bin/smoothforce" sweep --mesh "$mesh" --depth 1% --samples 60 --methods patch \
      -o "$work/sweep" >"$work/sweep.log" 2>&1 || { cat "$work/sweep.log"; fail "installed sweep exited with $?"; }
    ! grep -q "plot script" "$work/sweep.log" || { cat "$work/sweep.log"; fail "installed sweep: no plots"; }
    ! grep -q "Note:" "$work/sweep/index.html" || fail "index.html carries a note: $(grep Note: "$work/sweep/index.html")"
    n=0
    for png in "$work"/sweep/*.png; do
      [[ -f $png ]] || fail "no PNG plot in $work/sweep"
      [[ $(head -c 5 "${png%.png}.pdf" 2>/dev/null) == %PDF- ]] || fail "no PDF beside $png"
      n=$((n + 1))
    done
    echo "installed sweep found $prefix/share/smoothforce/sweep_plots.py: $n PNG plots, each with its PDF"
    ;;
  capi)
    prefix=$(cd "$1" && pwd) example=$2 work=$3 mesh=$4
    lib=$(libdir_of "$prefix")
    rm -rf "$work" && mkdir -p "$work"
    [[ -f $prefix/include/smoothforce.h ]] || fail "missing $prefix/include/smoothforce.h"
    if [[ $SF_SHARED_LIBS != 1 ]]; then
      echo "static libraries: a C program links the C API with the C++ runtime through CMake (SmoothForce::capi)"
      exit 0
    fi
    cc=${SF_CC:-cc}
    echo "$cc -std=c99 -Wall -Wextra -pedantic -Werror $example -I$prefix/include -L$lib -lsmoothforce_capi -lm"
    "$cc" -std=c99 -Wall -Wextra -pedantic -Werror "$example" -I"$prefix/include" -L"$lib" -lsmoothforce_capi -lm \
      -o "$work/example_c" || fail "compile the C example against the installed tree"
    LD_LIBRARY_PATH=$lib "$work/example_c" "$mesh" >"$work/out" || { cat "$work/out"; fail "example_c exited with $?"; }
    cat "$work/out"
    grep -q "^example_c: OK$" "$work/out" || fail "example_c did not report OK"
    ;;
  python)
    prefix=$(cd "$1" && pwd) example=$2 mesh=$3
    mod=$(find "$prefix" -name 'smoothforce.cpython-*.so' | head -n1)
    [[ -n $mod ]] || fail "no installed Python module under $prefix"
    [[ -f $(dirname "$mod")/smoothforce.pyi ]] || fail "no type stubs (smoothforce.pyi) beside $mod"
    out=$(cd / && PYTHONPATH=$(dirname "$mod") "${SF_PYTHON:-python3}" "$example" "$mesh") || { echo "$out"; fail "example.py"; }
    echo "$out"
    grep -q "^example_py: OK$" <<<"$out" || fail "example.py did not report OK"
    echo "installed module: $mod"
    ;;
  *)
    sed -n '2,13p' "$0"
    exit 2
    ;;
esac
