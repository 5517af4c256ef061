#!/usr/bin/env python3
"""The size limits of docs/ARCHITECTURE.md: no source file over 600 lines, no function over 80
lines, outside tests. Prints every violation and exits 1 if there is one.

    python3 scripts/code-limits.py [--max-file N] [--max-function N] [--list N] [DIR ...]
    python3 scripts/code-limits.py --self-test

Functions are found by matching braces in the code with comments and string literals blanked:
a function body is a '{' at namespace or class level whose head (the code since the previous
';', '{' or '}') holds a ')' and is not a control statement, a lambda or an initializer. Its
length runs from the first line of that head (the signature) to the closing brace. --list N
prints every function of N lines or more instead of checking.
"""
import argparse
import os
import re
import sys

SOURCE_DIRS = ["apps", "bench", "examples", "framework", "fuzz", "libs", "plugins"]
EXTENSIONS = (".cpp", ".h", ".hpp")
CONTROL = re.compile(r"\b(if|for|while|switch|catch|do|else)\b\s*\(")
LAMBDA = re.compile(r"\]\s*\(.*\)\s*(mutable\s*)?(->.*)?$", re.S)


def blank_comments_and_strings(src):
    """The source with comments and string/char literals replaced by spaces (lines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif src.startswith('R"', i) and re.match(r'R"([^(\s]*)\(', src[i:]):
            delim = re.match(r'R"([^(\s]*)\(', src[i:]).group(1)
            end = ")" + delim + '"'
            j = src.find(end, i)
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif src[i] in "\"'" and not (src[i] == "'" and i > 0 and src[i - 1].isalnum()):
            quote, j = src[i], i + 1
            while j < n and src[j] != quote and src[j] != "\n":
                j += 2 if src[j] == "\\" else 1
            out.append(quote + " " * (min(j, n) - i - 1) + (quote if j < n else ""))
            i = j + 1
        else:
            out.append(src[i])
            i += 1
    return "".join(out)


def functions(src):
    """(first line, last line, head) of every function body not nested in another one."""
    code = blank_comments_and_strings(src)
    found, stack, last = [], [], 0
    for i, c in enumerate(code):
        if c == "{":
            head = code[last:i].strip()
            in_function = any(f for f, _, _ in stack)
            is_function = (not in_function and ")" in head
                           and not CONTROL.search(head[-200:])
                           and not LAMBDA.search(head)
                           and not head.endswith("="))
            start = last + len(code[last:i]) - len(code[last:i].lstrip())
            stack.append((is_function, code.count("\n", 0, start) + 1,
                          head.split("\n")[-1].strip()[:70]))
            last = i + 1
        elif c == "}":
            if stack:
                is_function, first, head = stack.pop()
                if is_function:
                    found.append((first, code.count("\n", 0, i) + 1, head))
            last = i + 1
        elif c == ";":
            last = i + 1
    return found


def source_files(roots):
    for root in roots:
        for folder, dirs, files in os.walk(root):
            dirs[:] = [d for d in dirs if d not in ("tests", "build") and not d.startswith(".")]
            for f in sorted(files):
                if f.endswith(EXTENSIONS):
                    yield os.path.join(folder, f)


def self_test():
    body = "\n".join("  x += %d;" % k for k in range(98))
    long_fn = "int f(int x) {\n" + body + "\n  return x;\n}\n"  # 101 lines
    short_fn = "int g(int x) {\n" + "\n".join(body.split("\n")[:97]) + "\n  return x;\n}\n"
    tricky = ('namespace a {\nstruct S {\n  void m() const {\n    auto l = [&](int v) {\n'
              '      return v;\n    };\n    if (l(1)) {\n      s = "}{";  // }\n    }\n  }\n};\n}\n')
    cases = [(long_fn, [101]), (short_fn, [100]), (tricky, [8])]
    for src, want in cases:
        got = [b - a + 1 for a, b, _ in functions(src)]
        if got != want:
            print("self-test failed: lengths %s, expected %s for:\n%s" % (got, want, src[:200]))
            return 1
    print("self-test passed (%d cases)" % len(cases))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="*", help="folders to check (default: the source folders)")
    ap.add_argument("--max-file", type=int, default=600)
    ap.add_argument("--max-function", type=int, default=80)
    ap.add_argument("--list", type=int, default=0, metavar="N")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    roots = a.dirs or [d for d in SOURCE_DIRS if os.path.isdir(d)]
    problems, listed, files = [], [], 0
    for path in source_files(roots):
        files += 1
        with open(path, encoding="utf-8", errors="replace") as f:
            src = f.read()
        lines = src.count("\n")
        if lines > a.max_file:
            problems.append("%s: %d lines (limit %d)" % (path, lines, a.max_file))
        for first, last, head in functions(src):
            n = last - first + 1
            if a.list and n >= a.list:
                listed.append((n, path, first, head))
            elif n > a.max_function:
                problems.append("%s:%d: function of %d lines (limit %d): %s"
                                % (path, first, n, a.max_function, head))
    if a.list:
        for n, path, first, head in sorted(listed, reverse=True):
            print("%4d %s:%d %s" % (n, path, first, head))
        return 0
    for p in problems:
        print(p)
    print("%d files checked: %d over the limits" % (files, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
