#!/usr/bin/env bash
# Usage: install_example.sh BUILD_DIR SOURCE_DIR
#
# Checks that an installed asf is usable by an out-of-tree plugin project:
#   1. installs asf from BUILD_DIR into a temporary prefix (cmake --install),
#   2. configures and builds examples/custom_policy against it (find_package(asf COMPONENTS
#      contract)) with every non-contract dependency hidden, and checks the plugin links
#      libasf_contract and none of them,
#   3. runs the example's CTest tests (the conformance kit, run by the installed host),
#   4. installs the example plugin into the same prefix and checks that the installed host
#      (`asf plugins`) finds every installed plugin, the example's included,
#   5. builds a program against find_package(asf COMPONENTS graph) with the same packages
#      hidden, checks it links libasf_graph and none of the runtime's libraries, and runs it.
# Any failing step stops the script with a message naming it and a non-zero exit code.
# Set ASF_KEEP_TMP=1 to keep the temporary folder for inspection.
set -euo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: $0 BUILD_DIR SOURCE_DIR" >&2
  exit 2
fi
build_dir=$(realpath "$1")
source_dir=$(realpath "$2")
example_dir="$source_dir/examples/custom_policy"

work=$(mktemp -d "${TMPDIR:-/tmp}/asf-install-example.XXXXXX")
work=$(realpath "$work")
cleanup() {
  local rc=$?
  if [[ "${ASF_KEEP_TMP:-0}" == 1 || $rc -ne 0 ]]; then
    echo "install_example.sh: temporary files kept in $work" >&2
  else
    rm -rf "$work"
  fi
}
trap cleanup EXIT

prefix="$work/prefix"
example_build="$work/example-build"
step_name=""
step() {
  step_name="$*"
  echo
  echo "==> $*"
}
on_error() {
  echo >&2
  echo "install_example.sh: FAILED at step: $step_name" >&2
}
trap on_error ERR
fail() {
  echo "install_example.sh: FAILED: $*" >&2
  exit 1
}

# Only the installed plugin folder may be searched.
unset ASF_PLUGIN_PATH

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi

step "install asf from $build_dir into $prefix"
[[ -f "$build_dir/CMakeCache.txt" ]] || fail "$build_dir is not a CMake build folder"
[[ -d "$example_dir" ]] || fail "no example project at $example_dir"
cmake --install "$build_dir" --prefix "$prefix"
[[ -x "$prefix/bin/asf" ]] || fail "the install has no $prefix/bin/asf"
config=$(find "$prefix" -name asfConfig.cmake -print -quit)
[[ -n "$config" ]] || fail "the install has no asfConfig.cmake"
echo "asfConfig.cmake: $config"
"$prefix/bin/asf" --version

# The example asks for the contract alone, so it must configure and build as if everything
# else asf uses were not installed: those packages are hidden from find_package.
hidden=(OpenCV octomap GTest nlohmann_json BZip2 ZLIB CGAL mrpt-obs mrpt-maps mrpt-graphs
        mrpt-slam mrpt-graphslam mrpt-img mrpt-opengl)
hide=()
for pkg in "${hidden[@]}"; do hide+=("-DCMAKE_DISABLE_FIND_PACKAGE_$pkg=ON"); done

step "configure examples/custom_policy against the installed asf (contract dependencies only)"
cmake -S "$example_dir" -B "$example_build" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo --no-warn-unused-cli "${launcher[@]}" "${hide[@]}"

step "build examples/custom_policy"
cmake --build "$example_build" -j2
plugin="$example_build/plugins/policy_nearest_region.so"
[[ -f "$plugin" ]] || fail "the build did not produce $plugin"

step "the example plugin links the contract and none of the rest"
needed=$(readelf -d "$plugin" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
echo "$needed"
grep -q '^libasf_contract\.so' <<<"$needed" || fail "$plugin does not link libasf_contract"
if grep -E '^lib(asf_framework|asf_conformance|opencv|octomap|cholmod|mrpt-(maps|obs|slam|graphslam))' \
     <<<"$needed"; then
  fail "$plugin links more than the contract (above)"
fi

step "run the example's tests (conformance kit via the installed host)"
ctest --test-dir "$example_build" -N | tee "$work/ctest-list.txt"
grep -q "conformance.policy_nearest_region" "$work/ctest-list.txt" ||
  fail "the example has no conformance.policy_nearest_region test"
ctest --test-dir "$example_build" --output-on-failure --no-tests=error

step "install the example plugin into $prefix"
cmake --install "$example_build" --prefix "$prefix"

step "the installed host finds the installed plugins"
"$prefix/bin/asf" plugins
"$prefix/bin/asf" plugins --json >"$work/plugins.json"
shopt -s nullglob
installed=("$prefix"/lib*/asf/plugins/*.so "$prefix"/lib/*/asf/plugins/*.so)
shopt -u nullglob
[[ ${#installed[@]} -ge 2 ]] || fail "expected the reference plugins and the example in $prefix/lib/asf/plugins, found ${#installed[@]} files"
for so in "${installed[@]}"; do
  canonical=$(realpath "$so")
  grep -qF "\"$canonical\"" "$work/plugins.json" ||
    fail "asf plugins does not list the installed plugin $canonical"
done
grep -q '"name": "nearest_region"' "$work/plugins.json" ||
  fail "asf plugins does not list the example plugin nearest_region"

step "a program using the graph library alone (find_package(asf COMPONENTS graph))"
graph_src="$work/graph-consumer"
mkdir -p "$graph_src"
cat >"$graph_src/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(graph_consumer CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(asf REQUIRED COMPONENTS graph)
add_executable(postman main.cpp)
target_link_libraries(postman PRIVATE asf::graph)
CMAKE
cat >"$graph_src/main.cpp" <<'CPP'
// A triangle with a pendant edge: the Chinese postman walk repeats the pendant edge.
#include <asf/graph/routes.h>
#include <iostream>
int main() {
  asf::graph::Multigraph g;
  g.n = 4;
  g.edges = {{0, 1}, {1, 2}, {2, 0}, {2, 3}};
  std::cout << "postman length " << asf::graph::chinesePostman(g, 0).walk.length << "\n";
}
CPP
cmake -S "$graph_src" -B "$work/graph-build" -DCMAKE_PREFIX_PATH="$prefix" \
      --no-warn-unused-cli "${launcher[@]}" "${hide[@]}"
cmake --build "$work/graph-build" -j2
needed=$(readelf -d "$work/graph-build/postman" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
echo "$needed"
grep -q '^libasf_graph\.so' <<<"$needed" || fail "the graph program does not link libasf_graph"
if grep -E '^lib(asf_framework|asf_evaluation|asf_planning|opencv|octomap|mrpt-(maps|obs|slam))' \
     <<<"$needed"; then
  fail "the graph program links more than the graph library and the contract (above)"
fi
out=$(LD_LIBRARY_PATH="$prefix/lib:${LD_LIBRARY_PATH:-}" "$work/graph-build/postman")
echo "$out"
[[ "$out" == "postman length 5" ]] || fail "expected 'postman length 5', got '$out'"

echo
echo "install_example.sh: OK (${#installed[@]} installed plugins found by the installed host)"
