#!/usr/bin/env python3
"""Who may include and link whom (docs/ARCHITECTURE.md, "Layers"), checked on the source tree
and, with --build, on the built plugins. The rules:

  includes  a file of libs/<L> includes headers of lower libraries only (LIB_RANK: the contract
            at the bottom, evaluation at the top); above the libraries come the framework,
            then its conformance kit and studies/ (the host's protocols), then apps/, and
            each includes only what is below it; a file of plugins/<P> includes
            headers of libs/ and of its own folder only (a plugin never includes the framework,
            an application or another plugin's folder); no cycle between folders;
  links     no plugin .so depends on libasf_framework, directly or through one of asf's
            libraries (readelf's NEEDED, followed through build/lib).

Units are folders: libs/<L>, framework, framework/conformance, studies, apps/<A>, plugins/<P>, each
owning the headers under its include/ (and, for quoted includes, beside the
file). Tests, fuzz/, bench/ and examples/ are users, not checked. Includes are read as text
(`#include <...>` / `"..."`), so an include inside a comment counts.

Any violation fails the check, naming the files and include lines behind it.

    python3 scripts/layer-check.py [--build BUILD_DIR]
    python3 scripts/layer-check.py --self-test
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
SOURCES = (".cpp", ".h", ".hpp")
# The libraries from the bottom up (docs/ARCHITECTURE.md); equal ranks may not include each other.
LIB_RANK = {"libs/contract": 0, "libs/graph": 1, "libs/mapping": 2, "libs/io": 3, "libs/ros2_msgs": 3,
            "libs/navigation": 4, "libs/planning": 5, "libs/exploration": 6, "libs/evaluation": 7}
# Above the libraries (equal ranks may not include each other either).
TOP_RANK = {"framework": 100, "framework/conformance": 101, "studies": 101, "apps": 102}
SKIP_DIRS = {"tests", "fuzz", "bench", "examples", "build", ".git", "datasets", "docs", "configs"}


def unit_of(rel):
    """The unit (folder) a repository-relative path belongs to, or None outside the checked trees."""
    parts = rel.split("/")
    if parts[0] == "libs" and len(parts) > 2:
        return "libs/" + parts[1]
    if parts[0] == "plugins" and len(parts) > 2:
        return "plugins/" + parts[1]
    if parts[0] == "framework":
        return "framework/conformance" if len(parts) > 2 and parts[1] == "conformance" else "framework"
    if parts[0] == "studies":
        return "studies"
    if parts[0] == "apps" and len(parts) > 2:
        return "apps/" + parts[1]
    return None


def source_files(root):
    for top in ("libs", "plugins", "framework", "studies", "apps"):
        for d, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(x for x in dirs if x not in SKIP_DIRS)
            for f in sorted(files):
                if f.endswith(SOURCES):
                    yield os.path.relpath(os.path.join(d, f), root)


def header_owners(root, files):
    """Include path as written after an include/ folder -> the unit that owns it."""
    owners = {}
    for rel in files:
        parts = rel.split("/")
        if "include" in parts[:-1]:
            i = len(parts) - 1 - parts[::-1].index("include")
            owners.setdefault("/".join(parts[i + 1:]), unit_of(rel))
    return owners


def include_edges(root, files, owners):
    """{(from unit, to unit): [(file, header), ...]} for includes that cross units."""
    edges = {}
    for rel in files:
        src = unit_of(rel)
        text = open(os.path.join(root, rel), errors="replace").read()
        for quote, path in INCLUDE.findall(text):
            dst = None
            if quote == '"':
                beside = os.path.normpath(os.path.join(os.path.dirname(rel), path))
                if os.path.exists(os.path.join(root, beside)):
                    dst = unit_of(beside)
            if dst is None:
                dst = owners.get(path)
            if dst and dst != src:
                edges.setdefault((src, dst), []).append((rel, path))
    return edges


def rank(unit):
    """Height in the layers; None for a plugin (plugins stand beside each other on libs/)."""
    if unit.startswith("plugins/"):
        return None
    if unit.startswith("libs/"):
        if unit not in LIB_RANK:
            raise SystemExit(f"layer-check: {unit} has no rank: add it to LIB_RANK in {__file__}")
        return LIB_RANK[unit]
    return TOP_RANK[unit.split("/")[0] if unit.startswith("apps/") else unit]


def include_violations(edges):
    bad = set()
    for a, b in edges:
        ra, rb = rank(a), rank(b)
        if ra is None and not b.startswith("libs/"):
            bad.add(f"includes {a} -> {b}")
        if ra is not None and (rb is None or rb >= ra):
            bad.add(f"includes {a} -> {b}")
    return bad


def cycles(edges):
    """Each cycle between units once, as 'cycle A -> B -> ... -> A' from its smallest unit."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    found = set()

    def walk(start, node, path, seen):
        for nxt in sorted(graph.get(node, ())):
            if nxt == start:
                found.add("cycle " + " -> ".join(path + [start]))
            elif nxt not in seen and nxt > start:
                walk(start, nxt, path + [nxt], seen | {nxt})

    for start in sorted(graph):
        walk(start, start, [start], {start})
    return found


def needed(path):
    out = subprocess.run(["readelf", "-d", path], capture_output=True, text=True).stdout
    return re.findall(r"Shared library: \[([^\]]+)\]", out)


def link_violations(build):
    """'links <plugin>' for every plugin .so reaching libasf_framework through asf's libraries."""
    libdir = os.path.join(build, "lib")
    plugdir = os.path.join(libdir, "asf", "plugins")
    if not os.path.isdir(plugdir):
        raise SystemExit(f"layer-check: {plugdir}: no plugins built there")
    bad = set()
    for so in sorted(os.listdir(plugdir)):
        if not so.endswith(".so"):
            continue
        todo, seen = [os.path.join(plugdir, so)], set()
        while todo:
            for lib in needed(todo.pop()):
                if lib.startswith("libasf_") and lib not in seen:
                    seen.add(lib)
                    if os.path.exists(os.path.join(libdir, lib)):
                        todo.append(os.path.join(libdir, lib))
        if any(lib.startswith("libasf_framework.") for lib in seen):
            bad.add("links " + so[:-3])
    return bad


def check(root, build):
    files = list(source_files(root))
    edges = include_edges(root, files, header_owners(root, files))
    found = include_violations(edges) | cycles(edges)
    if build:
        found |= link_violations(build)
    for v in sorted(found):
        print("violation:", v)
        if v.startswith("includes "):
            a, b = v[len("includes "):].split(" -> ")
            for f, h in edges[(a, b)][:3]:
                print(f"    {f}: #include {h}")
    print(f"layer-check: {len(files)} files, {len(edges)} unit-to-unit include pairs, "
          f"{len(found)} violations" + ("" if build else " (plugin links not checked: no --build)"))
    return 1 if found else 0


def self_test():
    LIB_RANK.update({"libs/a": 0, "libs/b": 1})
    with tempfile.TemporaryDirectory() as root:
        def put(rel, text=""):
            os.makedirs(os.path.join(root, os.path.dirname(rel)), exist_ok=True)
            open(os.path.join(root, rel), "w").write(text)
        put("libs/a/include/asf/a.h")
        put("libs/b/include/asf/b.h", "#include <asf/a.h>\n")
        put("libs/b/src/b.cpp", '#include <asf/b.h>\n#include "local.h"\n')
        put("libs/b/src/local.h")
        put("framework/include/asf/run.h", "#include <asf/b.h>\n")
        put("plugins/p/p.cpp", '#include <asf/a.h>\n#include "core.h"\n')
        put("plugins/p/core.h")
        files = list(source_files(root))
        edges = include_edges(root, files, header_owners(root, files))
        assert set(edges) == {("libs/b", "libs/a"), ("framework", "libs/b"), ("plugins/p", "libs/a")}, edges
        assert include_violations(edges) == set() and cycles(edges) == set()
        put("libs/a/src/a.cpp", "#include <asf/run.h>\n")          # a library reaching up
        put("libs/graph/include/asf/g.h")
        put("libs/contract/src/c.cpp", "#include <asf/g.h>\n")   # the contract on a higher library
        put("plugins/p/q.cpp", "#include <asf/run.h>\n")           # a plugin on the framework
        put("plugins/r/r.cpp", '#include "../p/core.h"\n')        # another plugin's folder
        put("studies/include/asf/study.h", "#include <asf/run.h>\n")  # allowed: above the framework
        put("framework/src/run.cpp", "#include <asf/study.h>\n")     # the framework on a study
        files = list(source_files(root))
        edges = include_edges(root, files, header_owners(root, files))
        assert include_violations(edges) == {"includes libs/a -> framework", "includes plugins/p -> framework",
                                             "includes plugins/r -> plugins/p", "includes framework -> studies",
                                             "includes libs/contract -> libs/graph"}, include_violations(edges)
        assert cycles(edges) == {"cycle framework -> libs/b -> libs/a -> framework",
                                 "cycle framework -> studies -> framework"}, cycles(edges)
        assert check(root, None) == 1
        for rel in ("libs/a/src/a.cpp", "libs/contract/src/c.cpp", "plugins/p/q.cpp", "plugins/r/r.cpp",
                    "framework/src/run.cpp"):
            os.remove(os.path.join(root, rel))
        assert check(root, None) == 0
    print("layer-check self-test: ok")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", help="build directory: also check the plugins' links")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    return check(a.root, a.build)


if __name__ == "__main__":
    sys.exit(main())
