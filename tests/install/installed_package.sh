#!/usr/bin/env bash
# installed_package.sh BUILD_DIR SOURCE_DIR WORK_DIR
# Installs the build into a fresh prefix and uses it as an outsider would:
# examples/zdt1 built by CMake with find_package(stepstone) and by hand with
# pkg-config, both run to the known ZDT1 front (hypervolume 2/3 w.r.t. (1, 1));
# the installed binary's --version names the source tree's commit, and a run
# it writes stores that commit; the library's link interface (exported CMake
# targets, pkg-config file) names none of the dependencies of bench/ and
# reference/ (FLANN, liblz4, an HTTP client, Box2D).
set -euo pipefail
build=$1 source=$2 work=$3
fail() { echo "installed_package: $*" >&2; exit 1; }

rm -rf "$work" && mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log"

# (the library folder is lib/ or lib/<multiarch>/, as GNUInstallDirs chooses for the prefix)
for file in bin/stepstone include/stepstone/evo/pareto.hpp include/stepstone/core/version.hpp \
        share/stepstone/schema/0001_init.sql share/stepstone/queries/kb_growth.sql; do
    [[ -e $prefix/$file ]] || fail "not installed: $file"
done
for file in libstepstone_core.a libstepstone_service.a stepstoneConfig.cmake stepstone.pc; do
    [[ -n $(find "$prefix/lib" -name "$file") ]] || fail "not installed: $file"
done
for folder in bench reference; do
    [[ ! -e $prefix/include/stepstone/$folder ]] || fail "the $folder headers are not the library's but were installed"
done

# what a consumer of the library links: the lines (comments aside) of the exported targets,
# the package's config file and the pkg-config file (its Requires and Libs)
interface=$(find "$prefix/lib" \( -name 'stepstone*.cmake' -o -name stepstone.pc \) -exec grep -hv '^\s*#' {} +)
forbidden='flann|lz4|httplib|curl|box2d|stepstone::bench|stepstone_bench|stepstone::reference|stepstone_reference'
hits=$(grep -ioE "$forbidden" <<< "$interface" | sort -u | tr '\n' ' ' || true)
[[ -z $hits ]] || fail "the installed library's link interface names what only bench/ or reference/ needs: $hits"

# the Python module, where Debian's python3 looks under this prefix (when the build made it)
if [[ -n $(find "$build/python" -maxdepth 1 -name 'stepstone*.so' 2>/dev/null) ]]; then
    module=$(find "$prefix/lib" -path '*dist-packages/stepstone*.so')
    [[ -n $module ]] || fail "not installed: the Python module (lib/python3.X/dist-packages/stepstone*.so)"
    PYTHONPATH=$(dirname "$module") /usr/bin/python3 -c "
import stepstone, numpy as np
kb = stepstone.KnowledgeBase(width=2, channels=1, delta=1.5)
kb.observe(np.array([[0], [0], [1], [0]], dtype=np.float32), 0.5)
assert len(kb) == 1 and kb.records['count'][0] == 2, kb.records
" || fail "the installed Python module does not import or work"
fi

# CMake consumer: the example's own CMakeLists.txt in standalone mode
cmake -S "$source/examples/zdt1" -B "$work/zdt1-cmake" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" > "$work/zdt1-cmake.log" 2>&1 || { cat "$work/zdt1-cmake.log"; fail "find_package(stepstone) failed"; }
cmake --build "$work/zdt1-cmake" > "$work/zdt1-build.log" 2>&1 || { cat "$work/zdt1-build.log"; fail "zdt1 does not build against the installed package"; }
"$work/zdt1-cmake/example_zdt1" --generations 250 --seed 1 --min-hypervolume 0.65 || fail "zdt1 (CMake) missed the front"

# pkg-config consumer
export PKG_CONFIG_PATH=$(dirname "$(find "$prefix/lib" -name stepstone.pc)")
flags=$(pkg-config --cflags --libs stepstone) || fail "pkg-config does not resolve stepstone"
c++ -O2 "$source/examples/zdt1/main.cpp" -o "$work/zdt1-pc" $flags || fail "zdt1 does not build with pkg-config's flags"
"$work/zdt1-pc" --generations 250 --seed 1 --min-hypervolume 0.65 || fail "zdt1 (pkg-config) missed the front"

# the commit: from git directly, not from the build's own script
if git -C "$source" rev-parse HEAD > /dev/null 2>&1; then
    commit=$(git -C "$source" rev-parse HEAD | cut -c1-12)
    version=$("$prefix/bin/stepstone" --version)
    [[ $version == *"(commit $commit"* ]] || fail "--version says '$version', the tree is at $commit"
    cat > "$work/tiny.json" <<'JSON'
{"task": {"kind": "source", "steps_per_start": 100, "starts": 1},
 "ea": {"population_size": 4, "generations": 1},
 "kb": {"segment_width": 10, "delta": 1.0, "period": 1}}
JSON
    "$prefix/bin/stepstone" evolve --config "$work/tiny.json" --db "$work/run.db" --seed 1 --quiet
    release=$(sed -n 's/^project(stepstone VERSION \([0-9.]*\).*/\1/p' "$source/CMakeLists.txt")
    stored=$(sqlite3 "$work/run.db" "SELECT program_version FROM run")
    [[ $stored == "$release+$commit"* ]] || fail "the run stores program_version '$stored', expected $release+$commit"
fi
echo "installed_package: ok"
