#!/usr/bin/env python3
"""The layering of Filters/Core (Filters/Core/README.md), checked on the sources.

Every include of a core file must point to its own sub-package or one below:
    Support < Solvers < Mesh < Flows, Maps < Drawing < Remeshing   (Flows and Maps never include each other)
no include between core files may form a cycle, and the core never includes VTK.
Prints one line per violation and exits 1 if there is any.
"""
import os
import re
import sys

LAYER = {"Support": 0, "Solvers": 1, "Mesh": 2, "Flows": 3, "Maps": 3, "Drawing": 4, "Remeshing": 5}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.M)


def core_files(root):
    for package in LAYER:
        folder = os.path.join(root, package)
        for name in sorted(os.listdir(folder)):
            if name.endswith((".h", ".cxx")):
                yield package + "/" + name


def main(root):
    problems = []
    graph = {}
    files = list(core_files(root))
    if len(files) < 10:
        problems.append(f"only {len(files)} core files found under {root}")
    for path in files:
        package = path.split("/")[0]
        text = open(os.path.join(root, path), encoding="utf-8").read()
        graph[path] = []
        for target in INCLUDE.findall(text):
            head = target.split("/")[0]
            if target.startswith("vtk") or head == "Core":
                problems.append(f"{path}: includes {target} (the core is VTK-free and includes by sub-package)")
            if head not in LAYER:
                continue
            if not os.path.exists(os.path.join(root, target)):
                problems.append(f"{path}: includes {target}, which does not exist")
                continue
            graph[path].append(target)
            if head != package and LAYER[head] >= LAYER[package]:
                problems.append(f"{path}: includes {target}, which is not below {package}/")
    # Cycles between files (depth-first search).
    state = {}

    def visit(node, stack):
        state[node] = 1
        for nxt in graph.get(node, []):
            if state.get(nxt) == 1:
                problems.append("include cycle: " + " -> ".join(stack[stack.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = 2

    for node in graph:
        if node not in state:
            visit(node, [node])
    for p in problems:
        print("FAILED:", p)
    print(f"{len(files)} core files, {sum(len(v) for v in graph.values())} core includes checked")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
