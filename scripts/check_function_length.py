"""Checks that no library function is longer than the limit (150 lines),
except those listed in docs/architecture.md ("Long functions"), each there
with the reason it stays long.

A function here is a definition at namespace scope, as the project writes
them: a line starting in column 0 with a name and "(", its body opened by "{"
on the same or a following line, and closed by a "}" in column 0. Its length
counts from its first line to that "}".

usage: check_function_length.py [REPO_ROOT]   (plain python3, standard library)
Exit 0 when every function fits (or is listed), 1 otherwise.
"""
import re
import subprocess
import sys
from pathlib import Path

LIMIT = 150
FOLDERS = ("core", "linsolve", "assembly", "stage", "actors", "constraints", "contact", "solver", "scene")
SKIP = ("#", "//", "namespace", "}", "class ", "struct ", "enum ", "using ", "template", "extern", "static_assert")


def sources(root):
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", *FOLDERS], check=True, capture_output=True,
                                text=True).stdout.split()
        return [root / f for f in listed if f.endswith((".cc", ".h", ".cpp"))]
    except (OSError, subprocess.CalledProcessError):
        return [p for folder in FOLDERS for p in sorted((root / folder).glob("*")) if p.suffix in (".cc", ".h", ".cpp")]


def functions(path):
    """(first line, length, name) of each function defined at namespace scope in `path`."""
    lines = path.read_text(encoding="utf-8").split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        if line and not line[0].isspace() and not line.startswith(SKIP) and "(" in line:
            j = i
            while j < len(lines) and "{" not in lines[j] and ";" not in lines[j]:
                j += 1
            if j < len(lines) and "{" in lines[j] and ";" not in lines[j].split("{")[0]:
                opener = lines[j]
                if opener.rstrip().endswith("}") and opener.count("{") == opener.count("}"):
                    i = j + 1
                    continue
                k = j + 1
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                name = re.sub(r"\s+", " ", line)
                name = re.search(r"([\w:~<>]+)\s*\(", name).group(1) if re.search(r"([\w:~<>]+)\s*\(", name) else name
                yield i + 1, k - i + 1, name
                i = k + 1
                continue
        i += 1


def listed(root):
    """The names listed under docs/architecture.md's "Long functions"."""
    text = (root / "docs" / "architecture.md").read_text(encoding="utf-8")
    match = re.search(r"^## Long functions\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    if not match:
        return set()
    return set(re.findall(r"^- `([\w:~<>]+)`", match.group(1), re.M))


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent)
    allowed = listed(root)
    long = []
    count = 0
    for path in sources(root):
        for first, length, name in functions(path):
            count += 1
            if length > LIMIT and name not in allowed:
                long.append(f"{path.relative_to(root)}:{first}: {name} is {length} lines (limit {LIMIT})")
    for message in long:
        print(message)
    if long:
        print(f"check_function_length: FAILED, {len(long)} function(s) over {LIMIT} lines and not listed in "
              "docs/architecture.md (\"Long functions\", with the reason)")
        return 1
    print(f"check_function_length: OK ({count} functions, none over {LIMIT} lines but the {len(allowed)} listed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
