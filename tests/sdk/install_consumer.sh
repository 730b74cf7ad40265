#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then builds samples/c_minimal
# against it twice, as an outside project would: with CMake's find_package
# (shared and static) and with pkg-config; runs each on the cow.
#
# Checks the 0.x stable-API policy too: the SONAME carries the minor version
# and the package accepts only a request of the same minor version.
#
# usage: install_consumer.sh BUILD_DIR SOURCE_DIR WORK_DIR SOVERSION
set -euo pipefail
build=$1 source=$2 work=$3 soversion=$4

# The sample drags without waiting, so which intermediate frames get solved
# (and so the last solve's start) depends on timing: its results agree to
# the solver's tolerance, not bit for bit. Same counts and faces, vertices
# within 1e-4 of the cow's unit-sized bounding box.
same_mesh() {
  awk 'NR == FNR { a[FNR] = $0; next }
       { n = split(a[FNR], x); m = split($0, y)
         if (n != m) { print "line " FNR " differs: " a[FNR] " / " $0; bad = 1; exit }
         for (i = 1; i <= n; ++i) {
           d = x[i] - y[i]; if (d < 0) d = -d
           if (x[i] "" != y[i] "" && (x[i] !~ /^[-0-9.e+]+$/ || d > 1e-4)) {
             print "line " FNR " differs: " a[FNR] " / " $0; bad = 1; exit
           }
         } }
       END { if (!bad && FNR != length(a)) { print "line counts differ"; bad = 1 }; exit bad }' "$1" "$2"
}

rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"

echo "== find_package"
cmake -S "$source/samples/c_minimal" -B "$work/cmake" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release >"$work/configure.log"
cmake --build "$work/cmake" -j 2 >"$work/build.log"
"$work/cmake/c_minimal" model:cow "$work/cow-shared.off"
"$work/cmake/c_minimal_static" model:cow "$work/cow-static.off"
same_mesh "$work/cow-shared.off" "$work/cow-static.off"

echo "== pkg-config"
pc=$(dirname "$(find "$work/prefix" -name dualform.pc)")
flags=$(PKG_CONFIG_PATH=$pc pkg-config --cflags --libs dualform)
libdir=$(PKG_CONFIG_PATH=$pc pkg-config --variable=libdir dualform)
# shellcheck disable=SC2086
cc -std=c99 -Wall -Wextra -pedantic -Werror "$source/samples/c_minimal/main.c" $flags \
   -Wl,-rpath,"$libdir" -o "$work/c_minimal_pc"
"$work/c_minimal_pc" model:cow "$work/cow-pc.off"
same_mesh "$work/cow-shared.off" "$work/cow-pc.off"

echo "== exported symbols"
bad=$(nm -D --defined-only "$libdir/libdualform.so" | awk '{print $3}' | grep -v '^dfm_' || true)
if [ -n "$bad" ]; then
  echo "libdualform.so exports more than dfm_*:"; echo "$bad"; exit 1
fi
soname=$(objdump -p "$libdir/libdualform.so" | awk '/SONAME/ {print $2}')
echo "SONAME $soname"
[ "$soname" = "libdualform.so.$soversion" ]
if [ -f "$build/sdk/src/vulkan/libdualform_vulkan.so" ]; then
  echo "== the renderer"
  [ -f "$work/prefix/include/dualform/dualform_vulkan.h" ]
  [ -f "$libdir/libdualform_vulkan.so.$soversion" ]
  grep -q "dualform::vulkan" "$(find "$work/prefix" -name dualformTargets.cmake)"
fi
echo "== package version compatibility"
version_file=$(find "$work/prefix" -name dualformConfigVersion.cmake)
cat >"$work/compatible.cmake" <<'EOF'
string(REPLACE "." ";" parts "${PACKAGE_FIND_VERSION}")
list(GET parts 0 PACKAGE_FIND_VERSION_MAJOR)
list(GET parts 1 PACKAGE_FIND_VERSION_MINOR)
set(PACKAGE_FIND_VERSION_PATCH 0)
set(PACKAGE_FIND_VERSION_COUNT 2)
include(${VERSION_FILE})
if(NOT PACKAGE_VERSION_COMPATIBLE)
  message(FATAL_ERROR "not compatible")
endif()
EOF
compatible() {
  cmake -DPACKAGE_FIND_VERSION="$1" -DVERSION_FILE="$version_file" -P "$work/compatible.cmake"
}
compatible "$soversion"
major=${soversion%%.*}
if [ "$major" = 0 ]; then
  next_minor=$((${soversion#*.} + 1))
  if compatible "0.$next_minor" 2>/dev/null; then
    echo "a 0.x package must not accept a request for another minor version"; exit 1
  fi
fi
echo "install_consumer: ok"
