#!/bin/sh
# Installs the build into a temporary prefix and uses it as a user and an engine would:
# the installed programs find their data and import helper; libsinew.so exports exactly the
# functions its headers declare, its soname follows the version (CHANGELOG.md);
# small programs build against it with find_package(sinew) (shared, static, core; a cross-fade
# with IK in under 40 lines) and with
# pkg-config (sinew, sinew-core), and run.
#   test_install.sh BUILD_DIR SOURCE_DIR WORK_DIR CC
set -eu
build=$1 source=$2 work=$3 cc=$4
fixture="$source/tests/fixtures/two_bone.dae"
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
prefix="$work/prefix"
libdir=$(dirname "$(find "$prefix" -name libsinew.so | head -n 1)")
unset SINEW_DATA SINEW_IMPORT_HELPER

echo "== installed files"
for f in bin/sinew libexec/sinew/sinew-import libexec/sinew/sinew-import-assimp share/sinew/arm.muscles.json share/man/man1/sinew.1 \
         include/sinew/sinew.h include/sinew/version.h; do
    test -e "$prefix/$f" || { echo "missing: $f"; exit 1; }
done
test -e "$libdir/libsinew.a" && test -e "$libdir/libsinew_core.a" && test -e "$libdir/pkgconfig/sinew.pc" &&
    test -e "$libdir/cmake/sinew/sinewConfig.cmake"

echo "== the installed sinew, run from elsewhere"
cd "$work"
"$prefix/bin/sinew" --version
"$prefix/bin/sinew" info "$fixture" | head -n 3
# a format only Assimp reads: the lean helper hands over to sinew-import-assimp
"$prefix/bin/sinew" info "$source/tests/fixtures/no_ticks.x" -q | head -n 2
"$prefix/bin/sinew" render builtin:arm --size 64x48 -o "$work/arm.png"

echo "== the installed Python package, with nothing of the build tree"
if /usr/bin/python3 -c "import numpy, cffi" 2>/dev/null; then
    env -u SINEW_LIBRARY PYTHONPATH="$prefix/share/sinew/python" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c "
import sinew, sys
m = sinew.load(sys.argv[1])
assert sinew.library_path.startswith(sys.argv[2]), sinew.library_path
print(m, m.world(0, times=[0.0, 0.5]).shape)" "$fixture" "$prefix"
fi

echo "== exports: exactly the public API"
# the functions the installed headers declare (comments gone through the preprocessor) against
# what libsinew.so exports; the static libraries carry no global that is not sinew_*
"$cc" -E -P -I"$prefix/include" "$prefix/include/sinew/sinew.h" |
    grep -oE '\bsinew_[a-z0-9_]+[[:space:]]*\(' | sed 's/[[:space:]]*($//' | sort -u > "$work/declared"
nm -D --defined-only "$libdir/libsinew.so" | awk '{print $3}' | sort -u > "$work/exported"
if ! cmp -s "$work/declared" "$work/exported"; then
    echo "libsinew.so's exports differ from the headers' functions (< declared only, > exported only):"
    diff "$work/declared" "$work/exported" || true
    exit 1
fi
echo "$(wc -l < "$work/exported") functions exported, each declared in include/sinew"
for a in libsinew.a libsinew_core.a; do
    others=$(nm -g --defined-only "$libdir/$a" | awk 'NF == 3 {print $3}' | grep -v '^sinew_' || true)
    if [ -n "$others" ]; then echo "$a has global symbols other than sinew_*: $others"; exit 1; fi
done
echo "== a start loads only what every command needs"
# cJSON (the CLI's --json output), libxml2 (COLLADA), libepoxy (rendering), meshoptimizer (crowds'
# levels of detail) and Assimp (its helper) are loaded when first used, never at start
for f in "$prefix/bin/sinew" "$libdir/libsinew.so"; do
    needed=$(objdump -p "$f" | awk '$1 == "NEEDED" {print $2}')
    for lazy in libcjson libxml2 libepoxy libmeshoptimizer libassimp; do
        if echo "$needed" | grep -q "^$lazy"; then echo "$f links $lazy, which it loads on first use"; exit 1; fi
    done
    echo "$(basename "$f"): $(echo $needed)"
done
echo "== version and soname follow the ABI"
version=$(grep -oE 'SINEW_VERSION_STRING "[0-9.]+"' "$prefix/include/sinew/version.h" | grep -oE '[0-9.]+')
soname=$(objdump -p "$libdir/libsinew.so" | awk '$1 == "SONAME" {print $2}')
minor=$(echo "$version" | cut -d. -f1-2)
test "$soname" = "libsinew.so.$minor" || { echo "soname $soname for version $version"; exit 1; }
grep -q "^SONAME = \"$soname\"" "$source/python/sinew/_ffi.py" || { echo "python/sinew/_ffi.py does not load $soname"; exit 1; }
grep -q "^## $version" "$source/CHANGELOG.md" || { echo "CHANGELOG.md has no entry for $version"; exit 1; }
echo "version $version, soname $soname"

echo "== find_package(sinew)"
cmake -S "$source/tests/install/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_C_COMPILER="$cc" > "$work/consumer.log"
cmake --build "$work/consumer" >> "$work/consumer.log"
"$work/consumer/consumer_shared" "$fixture"
"$work/consumer/consumer_static" "$fixture"
"$work/consumer/consumer_core"
# a shared model's first clip fading into its second (Fox: Survey into Walk), a foreleg reaching by IK
fox="${SINEW_TESTDATA:-$source/../shared/testdata}/gltf-samples/Fox.glb"
test -e "$fox" || { echo "missing $fox (../shared/testdata)"; exit 1; }
test "$(wc -l < "$source/tests/install/consumer/crossfade.c")" -lt 40
"$work/consumer/consumer_crossfade" "$fox" b_LeftHand_011
ldd "$work/consumer/consumer_shared" | grep -q "$libdir/libsinew.so" ||
    { echo "consumer_shared does not use the installed libsinew.so"; exit 1; }

echo "== pkg-config"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pkg-config --modversion sinew
# shellcheck disable=SC2046
"$cc" -o "$work/pc_shared" "$source/tests/install/consumer/main.c" $(pkg-config --cflags --libs sinew) \
      -Wl,-rpath,"$libdir"
"$work/pc_shared" "$fixture"
# shellcheck disable=SC2046
"$cc" -o "$work/pc_core" "$source/tests/install/consumer/core.c" $(pkg-config --cflags --libs sinew-core)
"$work/pc_core"
echo "install test passed"
