#!/usr/bin/env python3
"""Who may include and link whom (docs/ARCHITECTURE.md, "Layers"), checked on the source tree
and, with --build, on the built plugins. The rules:

  includes  a file of libs/<L> includes headers of lower libraries only (LIB_RANK: the contract
            at the bottom, evaluation at the top); a file of plugins/<P> includes
            headers of libs/ and of its own folder only (a plugin never includes the framework,
            an application or another plugin's folder); no cycle between folders;
  links     no plugin .so depends on libasf_framework, directly or through one of asf's
            libraries (readelf's NEEDED, followed through build/lib).

Units are folders: libs/<L>, framework, framework/conformance, apps/<A>, plugins/<P>, each
owning the headers under its include/ (and, for quoted includes, beside the
file). Tests, fuzz/, bench/ and examples/ are users, not checked. Includes are read as text
(`#include <...>` / `"..."`), so an include inside a comment counts.

The re-layout is done in slices, so today's violations are listed in a baseline
(scripts/layer-baseline.txt, one "includes A -> B" or "links P" per line). The check fails on
a violation not in the baseline and on a baseline line that is no longer a violation (delete
it: the list only shrinks).

    python3 scripts/layer-check.py [--build BUILD_DIR] [--baseline FILE] [--write-baseline]
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
    if parts[0] == "apps" and len(parts) > 2:
        return "apps/" + parts[1]
    return None


def source_files(root):
    for top in ("libs", "plugins", "framework", "apps"):
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


def include_violations(edges):
    bad = set()
    for a, b in edges:
        for lib in (a, b):
            if lib.startswith("libs/") and lib not in LIB_RANK:
                raise SystemExit(f"layer-check: {lib} has no rank: add it to LIB_RANK in {__file__}")
        if a.startswith("libs/") and (not b.startswith("libs/") or LIB_RANK[b] >= LIB_RANK[a]):
            bad.add(f"includes {a} -> {b}")
        if a.startswith("plugins/") and not b.startswith("libs/"):
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
    """('links <plugin>' for every plugin .so reaching libasf_framework through asf's libraries,
    the plugins built)."""
    libdir = os.path.join(build, "lib")
    plugdir = os.path.join(libdir, "asf", "plugins")
    if not os.path.isdir(plugdir):
        raise SystemExit(f"layer-check: {plugdir}: no plugins built there")
    bad, built = set(), set()
    for so in sorted(os.listdir(plugdir)):
        if not so.endswith(".so"):
            continue
        built.add(so[:-3])
        todo, seen = [os.path.join(plugdir, so)], set()
        while todo:
            for lib in needed(todo.pop()):
                if lib.startswith("libasf_") and lib not in seen:
                    seen.add(lib)
                    if os.path.exists(os.path.join(libdir, lib)):
                        todo.append(os.path.join(libdir, lib))
        if any(lib.startswith("libasf_framework.") for lib in seen):
            bad.add("links " + so[:-3])
    return bad, built


def check(root, build, baseline_path, write):
    files = list(source_files(root))
    edges = include_edges(root, files, header_owners(root, files))
    found = include_violations(edges) | cycles(edges)
    built = set()
    if build:
        links, built = link_violations(build)
        found |= links
    if write:
        with open(baseline_path, "w") as f:
            f.write("# Layer violations still to remove (scripts/layer-check.py); the list only shrinks.\n")
            f.writelines(v + "\n" for v in sorted(found))
        print(f"layer-check: wrote {len(found)} lines to {baseline_path}")
        return 0
    known = set()
    if os.path.exists(baseline_path):
        known = {l.strip() for l in open(baseline_path) if l.strip() and not l.startswith("#")}
    # a plugin not built here (an optional component) is not checked
    known = {k for k in known if not k.startswith("links ") or k[len("links "):] in built}
    new, gone = sorted(found - known), sorted(known - found)
    for v in new:
        print("new violation:", v)
        if v.startswith("includes "):
            a, b = v[len("includes "):].split(" -> ")
            for f, h in edges[(a, b)][:3]:
                print(f"    {f}: #include {h}")
    for v in gone:
        print(f"no longer a violation (delete the line from {baseline_path}):", v)
    print(f"layer-check: {len(files)} files, {len(edges)} unit-to-unit include pairs, "
          f"{len(found)} violations ({len(found & known)} in the baseline), {len(new)} new, {len(gone)} gone")
    return 1 if new or gone else 0


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
        files = list(source_files(root))
        edges = include_edges(root, files, header_owners(root, files))
        assert include_violations(edges) == {"includes libs/a -> framework", "includes plugins/p -> framework",
                                             "includes plugins/r -> plugins/p",
                                             "includes libs/contract -> libs/graph"}, include_violations(edges)
        assert cycles(edges) == {"cycle framework -> libs/b -> libs/a -> framework"}, cycles(edges)
        base = os.path.join(root, "baseline.txt")
        open(base, "w").write("includes libs/a -> framework\nincludes plugins/p -> framework\n"
                              "includes libs/contract -> libs/graph\n"
                              "includes plugins/r -> plugins/p\ncycle framework -> libs/b -> libs/a -> framework\n")
        assert check(root, None, base, False) == 0
        open(base, "a").write("includes libs/b -> framework\n")  # stale: must be deleted
        assert check(root, None, base, False) == 1
        open(base, "w").write("includes libs/a -> framework\n")  # two new ones
        assert check(root, None, base, False) == 1
    print("layer-check self-test: ok")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", help="build directory: also check the plugins' links")
    ap.add_argument("--baseline", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                       "layer-baseline.txt"))
    ap.add_argument("--write-baseline", action="store_true", help="record today's violations")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    return check(a.root, a.build, a.baseline, a.write_baseline)


if __name__ == "__main__":
    sys.exit(main())
