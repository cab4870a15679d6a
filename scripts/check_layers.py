#!/usr/bin/env python3
"""Checks SuperDex's include graph against its layers.

The library's folders form layers, lowest first, listed in the section
"Layers" of docs/architecture.md. A library file may include another folder
only where that folder's layer is at or below its own; neither the folders nor
the files may include each other in a cycle; and the code above the library
(perf/, examples/, python/) reaches it through installed headers only: the
umbrella <superdex/superdex.h> and, per folder, the internal headers the docs
list for it. tests/ and scripts/ are exempt. Files not tracked by git (build
folders) are ignored; outside a git checkout, folders named build* are.

usage: check_layers.py [REPO_ROOT]    (default: the repository holding this script)
Exits 0 and prints "check_layers: OK (N files, M includes)" when the tree
keeps the rules, 1 after listing every violation, 2 when docs/architecture.md
has no usable Layers section. Standard library only. Run in ctest as
`layering`; tests/layering/test_check_layers.py shows that it can fail.
"""
from __future__ import annotations

import os
import posixpath
import re
import subprocess
import sys
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

ARCHITECTURE_DOC = "docs/architecture.md"
LAYERS_HEADING = "## Layers"
SOURCE_SUFFIXES = (".h", ".cc", ".cpp", ".hpp")
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
LAYER_ORDER_RE = re.compile(r"^Layer order:\s*(.*)$")
ABOVE_RE = re.compile(r"^Above the library, through installed headers only:\s*(.*)$")
MAY_ALSO_RE = re.compile(r"^([A-Za-z0-9_.-]+)/ may also include:\s*(.*)$")


class LayerSpecError(Exception):
    """docs/architecture.md lacks the Layers section or it cannot be read."""


@dataclass
class LayerSpec:
    layers: list[str]                  # lowest first: folders, then root headers (superdex.h)
    above: list[str]                   # folders above the library (perf, examples, python)
    also_allowed: dict[str, set[str]]  # above folder -> internal headers it may include

    def layer_of(self, unit: str) -> int:
        return self.layers.index(unit)

    @property
    def folders(self) -> list[str]:
        return [name for name in self.layers if "." not in name]

    @property
    def root_headers(self) -> list[str]:
        return [name for name in self.layers if "." in name]


@dataclass
class Include:
    source: str        # including file, relative to the root
    line: int
    target: str        # included file, relative to the root (superdex/ stripped)
    quoted: bool       # "..." rather than <superdex/...>


@dataclass
class Report:
    violations: list[str] = field(default_factory=list)
    files: int = 0
    includes: int = 0


def _split_list(text: str, separator: str) -> list[str]:
    items = [item.strip().rstrip(".").strip() for item in re.split(separator, text)]
    return [item for item in items if item]


def _normalize_doc_line(line: str) -> str:
    line = line.strip()
    for marker in ("- ", "* "):
        if line.startswith(marker):
            line = line[len(marker):].strip()
    return line.strip("`").strip()


def read_layer_spec(root: Path) -> LayerSpec:
    """Parses the Layers section of docs/architecture.md; raises LayerSpecError."""
    doc = root / ARCHITECTURE_DOC
    try:
        lines = doc.read_text(encoding="utf-8").splitlines()
    except OSError as error:
        raise LayerSpecError(f"cannot read {doc}: {error}") from None
    try:
        start = [line.strip() for line in lines].index(LAYERS_HEADING)
    except ValueError:
        raise LayerSpecError(f"{doc}: no section '{LAYERS_HEADING}'") from None
    section = []
    for line in lines[start + 1:]:
        if line.startswith("# ") or line.startswith("## "):
            break
        section.append(_normalize_doc_line(line))

    orders = [m.group(1) for m in map(LAYER_ORDER_RE.match, section) if m]
    aboves = [m.group(1) for m in map(ABOVE_RE.match, section) if m]
    if len(orders) != 1:
        raise LayerSpecError(f"{doc}: section '{LAYERS_HEADING}' needs exactly one line "
                             f"'Layer order: core → linsolve → ...' (found {len(orders)})")
    if len(aboves) != 1:
        raise LayerSpecError(f"{doc}: section '{LAYERS_HEADING}' needs exactly one line "
                             f"'Above the library, through installed headers only: ...' "
                             f"(found {len(aboves)})")
    layers = _split_list(orders[0], r"→|->")
    above = [name.rstrip("/") for name in _split_list(aboves[0], ",")]
    if len(layers) < 2 or len(set(layers)) != len(layers):
        raise LayerSpecError(f"{doc}: the layer order must name two or more distinct layers: "
                             f"{orders[0]!r}")
    if not above or set(above) & set(layers):
        raise LayerSpecError(f"{doc}: the folders above the library must be named, none of "
                             f"them a layer: {aboves[0]!r}")
    spec = LayerSpec(layers, above, {name: set() for name in above})
    folders = set(spec.folders)
    for m in filter(None, map(MAY_ALSO_RE.match, section)):
        name, headers = m.group(1), _split_list(m.group(2), ",")
        if name not in spec.also_allowed:
            raise LayerSpecError(f"{doc}: '{name}/ may also include' names no folder above "
                                 f"the library ({', '.join(above)})")
        for header in headers:
            if header.split("/")[0] not in folders or "/" not in header:
                raise LayerSpecError(f"{doc}: '{name}/ may also include' lists {header!r}, "
                                     f"which is in no layer folder")
            spec.also_allowed[name].add(header)
    return spec


def list_files(root: Path) -> list[str]:
    """Every file of the tree, relative to root: git's tracked files in a
    checkout whose top is root, else a walk that skips build* and hidden folders."""
    try:
        top = subprocess.run(["git", "-C", str(root), "rev-parse", "--show-toplevel"],
                             capture_output=True, text=True, check=True).stdout.strip()
        if top and os.path.samefile(top, root):
            out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"],
                                 capture_output=True, text=True, check=True).stdout
            return sorted(p for p in out.split("\0") if p and (root / p).is_file())
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for directory, subdirs, names in os.walk(root):
        subdirs[:] = [d for d in subdirs if not d.startswith(("build", "."))]
        rel = Path(directory).relative_to(root)
        files.extend((rel / name).as_posix() for name in names)
    return sorted(files)


def unit_of(path: str, spec: LayerSpec) -> str | None:
    """The layer (folder or root header) a repository path belongs to, if any."""
    if path in spec.root_headers:
        return path
    head = path.split("/")[0]
    if "/" in path and head in spec.folders:
        return head
    return None


def read_includes(root: Path, source: str, files: set[str]) -> list[Include]:
    """The includes of one file that name a file of the repository: every
    <superdex/...>, and every "..." that resolves, relative to the including
    file's folder, to a file of the tree."""
    includes = []
    text = (root / source).read_text(encoding="utf-8", errors="replace")
    for number, line in enumerate(text.splitlines(), start=1):
        m = INCLUDE_RE.match(line)
        if not m:
            continue
        delimiter, name = m.groups()
        if delimiter == "<":
            if name.startswith("superdex/"):
                includes.append(Include(source, number, name[len("superdex/"):], quoted=False))
        else:
            target = posixpath.normpath(posixpath.join(posixpath.dirname(source), name))
            if target in files:
                includes.append(Include(source, number, target, quoted=True))
    return includes


def check_upward(include: Include, spec: LayerSpec) -> str | None:
    """A library file's include that points to a higher layer (or to no layer)."""
    source_unit = unit_of(include.source, spec)
    target_unit = unit_of(include.target, spec)
    where = f"{include.source}:{include.line} includes {include.target}"
    if target_unit is None:
        if include.quoted:
            return f"{where}: {source_unit} may not include a file outside the library"
        return f"{where}: superdex/{include.target} is in no layer of {ARCHITECTURE_DOC}"
    i, j = spec.layer_of(source_unit), spec.layer_of(target_unit)
    if j > i:
        return (f"{where}: {source_unit} (layer {i}) may not include "
                f"{target_unit} (layer {j})")
    return None


def check_above(include: Include, folder: str, spec: LayerSpec) -> str | None:
    """An include of perf/, examples/ or python/ that is not an installed header
    allowed to that folder."""
    where = f"{include.source}:{include.line} includes {include.target}"
    if include.quoted:
        if unit_of(include.target, spec) is None:
            return None
        return (f"{where} by a relative path: {folder} reaches the library through "
                f"<superdex/...> only")
    if include.target in spec.root_headers or include.target in spec.also_allowed[folder]:
        return None
    allowed = [f"<superdex/{h}>" for h in spec.root_headers + sorted(spec.also_allowed[folder])]
    return f"{where}: {folder}/ may include only {', '.join(allowed)} ({ARCHITECTURE_DOC})"


def strongly_connected_components(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's algorithm, iterative; components in no particular order."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, successors = work[-1]
            advanced = False
            for succ in successors:
                if succ not in index:
                    index[succ] = low[succ] = len(index)
                    stack.append(succ)
                    on_stack.add(succ)
                    work.append((succ, iter(sorted(graph.get(succ, ())))))
                    advanced = True
                    break
                if succ in on_stack:
                    low[node] = min(low[node], index[succ])
            if advanced:
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                components.append(sorted(component))
    return components


def shortest_path(graph: dict[str, set[str]], source: str, target: str,
                  within: set[str]) -> list[str]:
    """The shortest path source → ... → target through nodes of within (breadth
    first); with source == target, the shortest cycle through it."""
    previous = {source: None}
    queue = deque([source])
    while queue:
        node = queue.popleft()
        for succ in sorted(graph.get(node, ())):
            if succ == target:
                path = [node]
                while previous[path[-1]] is not None:
                    path.append(previous[path[-1]])
                return list(reversed(path)) + [target]
            if succ in within and succ not in previous:
                previous[succ] = node
                queue.append(succ)
    raise AssertionError(f"no path {source} → {target} within its component")


def _graph_of(edges: dict[tuple[str, str], Include]) -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    return graph


def _describe_cycle(kind: str, cycle: list[str], edges: dict[tuple[str, str], Include]) -> str:
    steps = [edges[(a, b)] for a, b in zip(cycle, cycle[1:])]
    evidence = "; ".join(f"{s.source}:{s.line} includes {s.target}" for s in steps)
    return f"{kind} cycle: {' → '.join(cycle)} ({evidence})"


def find_folder_cycles(edges: dict[tuple[str, str], Include], spec: LayerSpec) -> list[str]:
    """Every cycle of the folder graph closed by an upward include: per upward
    edge a → b inside a strongly connected component, a → b and then the
    shortest way back to a (every folder cycle has an upward edge)."""
    graph = _graph_of(edges)
    cycles = set()
    for component in map(set, strongly_connected_components(graph)):
        for a, b in edges:
            if a in component and b in component and spec.layer_of(b) > spec.layer_of(a):
                cycle = [a] + shortest_path(graph, b, a, component)
                ring = cycle[:-1]
                turn = ring.index(min(ring))  # one rotation per cycle, however found
                ring = ring[turn:] + ring[:turn]
                cycles.add(tuple(ring + ring[:1]))
    return sorted(_describe_cycle("folder", list(cycle), edges) for cycle in cycles)


def find_file_cycles(edges: dict[tuple[str, str], Include]) -> list[str]:
    """One cycle per strongly connected component of the file graph that has
    one: the shortest through its first file."""
    graph = _graph_of(edges)
    reports = []
    for component in strongly_connected_components(graph):
        first = component[0]
        if len(component) == 1 and first not in graph[first]:
            continue
        cycle = shortest_path(graph, first, first, set(component))
        report = _describe_cycle("file", cycle, edges)
        if len(component) > len(cycle) - 1:
            report += f"; {len(component)} files include each other: {', '.join(component)}"
        reports.append(report)
    return sorted(reports)


def check_tree(root: Path) -> Report:
    """Every violation of the layering rules in the tree at root."""
    spec = read_layer_spec(root)
    all_files = list_files(root)
    file_set = set(all_files)
    report = Report()
    folder_edges: dict[tuple[str, str], Include] = {}
    file_edges: dict[tuple[str, str], Include] = {}
    for path in all_files:
        library_unit = unit_of(path, spec)
        head = path.split("/")[0]
        above = head if "/" in path and head in spec.above else None
        if (library_unit is None and above is None) or not path.endswith(SOURCE_SUFFIXES):
            continue
        report.files += 1
        for include in read_includes(root, path, file_set):
            report.includes += 1
            if library_unit is not None:
                problem = check_upward(include, spec)
                target_unit = unit_of(include.target, spec)
                if target_unit is not None and target_unit != library_unit:
                    folder_edges.setdefault((library_unit, target_unit), include)
            else:
                problem = check_above(include, above, spec)
            if problem:
                report.violations.append(problem)
            if include.target in file_set:
                file_edges.setdefault((path, include.target), include)
    report.violations += find_folder_cycles(folder_edges, spec)
    report.violations += find_file_cycles(file_edges)
    return report


def main(argv: list[str]) -> int:
    if len(argv) > 2 or (len(argv) == 2 and argv[1].startswith("-")):
        print("usage: check_layers.py [REPO_ROOT]", file=sys.stderr)
        return 2
    root = Path(argv[1]) if len(argv) == 2 else Path(__file__).resolve().parent.parent
    try:
        report = check_tree(root.resolve())
    except LayerSpecError as error:
        print(f"check_layers: error: {error}", file=sys.stderr)
        return 2
    for violation in report.violations:
        print(violation)
    if report.violations:
        print(f"check_layers: FAILED, {len(report.violations)} violation(s) "
              f"({report.files} files, {report.includes} includes; rules in {ARCHITECTURE_DOC})")
        return 1
    print(f"check_layers: OK ({report.files} files, {report.includes} includes)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
