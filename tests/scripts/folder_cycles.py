#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""folder_cycles.py ROOT: the folder include graph of libtkr has no cycle.

A file in source/FOLDER/ or include/tkr/FOLDER/ belongs to FOLDER; each
`#include <tkr/OTHER/...>` of it is an edge FOLDER -> OTHER. Prints the
graph (doc/architecture.md states it) and fails, naming the files of every
edge on a cycle, if a folder reaches itself. Issue 52: the parameters layer
included gait/ and wear/ to declare their models' entries (two cycles).
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r"^\s*#\s*include\s*<tkr/([a-z_]+)/[^>]+>", re.M)


def folder_of(path, root):
    parts = path.relative_to(root).parts
    if parts[0] == "source":
        return parts[1]
    if parts[:2] == ("include", "tkr"):
        return parts[2]
    return None


def include_graph(root):
    """{folder: {other folder: [files that include it]}}"""
    graph = {}
    for pattern in ("source/**/*.cc", "source/**/*.h", "include/tkr/**/*.h"):
        for path in sorted(root.glob(pattern)):
            folder = folder_of(path, root)
            if folder is None or path.parent == root / "source":
                continue
            edges = graph.setdefault(folder, {})
            for other in INCLUDE.findall(path.read_text()):
                if other != folder:
                    edges.setdefault(other, []).append(str(path.relative_to(root)))
    return graph


def cycle_edges(graph):
    """The edges that lie on some cycle: a -> b with b reaching a."""

    def reaches(start, goal):
        seen, todo = set(), [start]
        while todo:
            node = todo.pop()
            if node == goal:
                return True
            if node not in seen:
                seen.add(node)
                todo.extend(graph.get(node, {}))
        return False

    return [(a, b) for a in sorted(graph) for b in sorted(graph[a]) if reaches(b, a)]


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    graph = include_graph(root)
    if len(graph) < 5:
        sys.exit(f"FAIL: only {len(graph)} folders found under {root}")
    for folder in sorted(graph):
        print(f"{folder} -> {', '.join(sorted(graph[folder])) or '(none)'}")
    bad = cycle_edges(graph)
    for a, b in bad:
        print(f"FAIL: {a} -> {b} lies on a cycle; included by " f"{', '.join(graph[a][b])}")
    if bad:
        sys.exit(1)
    print(f"ok: {len(graph)} folders, no cycle")


if __name__ == "__main__":
    main()
