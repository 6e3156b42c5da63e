#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Checks the include graph of host/ and runtime/ against the layer table (docs/design.md
"Architecture"): every #include <smoothforce/<m>/...> must name the file's own module or one
it may depend on, quoted includes may name only a private header beside the file or a kernels/
header, and the file-level include graph must have no cycle. Library code never uses
tbb::global_control (process-wide); thread limits go through a tbb::task_arena.

usage: tools/check_layers.py [REPO_ROOT]     exit status 0 when clean, 1 otherwise
Prints the module edges with their include counts and the number of levels.
"""
import os
import re
import sys

# module -> modules it may include (directly or not); the layer table of docs/design.md.
ALLOWED = {
    "base": set(),
    "mesh": {"base"},
    "patch": {"base", "mesh"},
    "query": {"base", "mesh", "patch"},
    "force": {"base", "mesh", "patch", "query"},
    "opencl": {"base", "mesh", "patch", "query"},
    "sweep": {"base", "mesh", "patch", "query", "force", "opencl"},
    "runtime": {"base", "mesh", "patch", "query", "force"},
    "capi": {"base", "mesh", "patch", "query", "force", "runtime"},
}
GENERATED = {"smoothforce/version.h": "base", "smoothforce/config.h": "base"}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def module_of(rel):
    parts = rel.split("/")
    if parts[0] == "runtime":
        return "runtime"
    if parts[0] == "host" and len(parts) > 2 and parts[1] in ALLOWED:
        return parts[1]
    return None


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    kernels = set(os.listdir(os.path.join(root, "kernels"))) | {"sf_kernel_sources.h"}
    files = {}  # repo-relative path -> module
    for top in ("host", "runtime"):
        for d, _, names in os.walk(os.path.join(root, top)):
            for n in names:
                if n.endswith((".h", ".cpp")):
                    rel = os.path.relpath(os.path.join(d, n), root)
                    files[rel] = module_of(rel)
    public = {}  # "smoothforce/<m>/x.h" -> repo-relative path
    for rel in files:
        if "/include/smoothforce/" in rel:
            public[rel.split("/include/", 1)[1]] = rel

    errors, edges, graph = [], {}, {rel: [] for rel in files}
    for rel, mod in sorted(files.items()):
        if mod is None:
            if rel != "host/include/smoothforce/smoothforce.h":
                errors.append(f"{rel}: not in a module folder")
            continue
        text = open(os.path.join(root, rel), encoding="utf-8").read()
        if "global_control" in text:
            errors.append(f"{rel}: tbb::global_control changes the whole process's thread limit; "
                          "use a tbb::task_arena")
        for m in INCLUDE.finditer(text):
            kind, name = m.group(1), m.group(2)
            line = text.count("\n", 0, m.start()) + 1
            where = f"{rel}:{line}: #include {kind}{name}{'>' if kind == '<' else kind}"
            if kind == '"':
                beside = os.path.join(os.path.dirname(rel), name)
                if beside in files and "/include/" not in beside:
                    graph[rel].append(beside)
                elif name not in kernels:
                    errors.append(f"{where}: a quoted include must name a private header beside the file "
                                  "or a kernels/ header")
                continue
            if not name.startswith("smoothforce/"):
                continue  # system and third-party headers
            target = GENERATED.get(name)
            if target is None:
                if name not in public:
                    errors.append(f"{where}: no such public header")
                    continue
                graph[rel].append(public[name])
                target = files[public[name]]
            if target != mod:
                edges[(mod, target)] = edges.get((mod, target), 0) + 1
                if target not in ALLOWED[mod]:
                    errors.append(f"{where}: {mod} may not include {target} (layer order, docs/design.md)")

    # cycles in the file graph (iterative DFS)
    state = {}
    for start in graph:
        if start in state:
            continue
        stack = [(start, iter(graph[start]))]
        state[start] = 1
        path = [start]
        while stack:
            node, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                state[node] = 2
                stack.pop()
                path.pop()
            elif state.get(nxt) == 1:
                errors.append("include cycle: " + " -> ".join(path[path.index(nxt):] + [nxt]))
            elif nxt not in state:
                state[nxt] = 1
                stack.append((nxt, iter(graph[nxt])))
                path.append(nxt)

    level, visiting = {}, set()

    def depth(m):  # longest chain of module edges below m; a module cycle is an error
        if m in visiting:
            errors.append(f"module cycle through {m}")
            return 0
        if m not in level:
            visiting.add(m)
            level[m] = 1 + max((depth(t) for (s, t) in edges if s == m), default=0)
            visiting.discard(m)
        return level[m]

    levels = max(map(depth, ALLOWED))
    for (s, t), n in sorted(edges.items()):
        print(f"{s} -> {t}: {n} includes")
    print(f"{len(files)} files, {len(edges)} module edges, {levels} levels, "
          f"{len(errors)} violations")
    for e in errors:
        print("error:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
