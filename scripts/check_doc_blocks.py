"""Checks that the fenced code blocks of the README and the docs still compile, run or name things
that exist (ctest doc_blocks): README.md, docs/*.md, perf/harness/README.md, examples/*/README.md,
tests/fuzz/README.md. Prints one line per block (file:line, language, verdict); exit status 1 when
any block fails.

usage: check_doc_blocks.py REPO_ROOT BUILD_DIR   (BUILD_DIR: a build with examples, perf and mochi)

cpp     shown verbatim (stripped lines, a contiguous run) in a file under examples/, tests/ or perf/
        that BUILD_DIR compiles (compile_commands.json): ok, ctest compiles and runs that file.
        Otherwise compiled (-fsyntax-only, the compiler and flags of examples/hello/hello.cpp): a
        block with `int main` as is, any other inside `void DocBlock() { using namespace superdex;
        ... }` (its leading #includes on top) after PRELUDE's declarations of the names it uses but
        does not declare. The wrapped blocks compile as one file; when that fails, the blocks its
        errors name (#line: the doc's lines) compile alone, the others together again.
        Not run, so what they would compute is not checked.
python  a file's blocks run in order as one script (PYTHONPATH=BUILD_DIR/python, a temporary working
        directory, 120 s); a file whose blocks do not import mochi is skipped. Output not compared.
sh      not run. Per command (continuations joined, comments dropped, `[--opt ARG]` unbracketed):
        repository paths (scripts/, examples/, perf/, tests/, docs/, python/, cmake/) exist;
        build/.../superdex_* programs exist in BUILD_DIR and list every --option after them in their
        --help; `cmake --build D --target T` and `make -C D T` name a target of BUILD_DIR. Not
        checked: tokens with $ or globs, outputs (after --out/--prefix; results/, /tmp), other
        paths (build/python, /usr/...), option values, the order of subcommands.
Other languages (cmake) and untagged blocks (usage synopses, program output, diagrams): listed only.
"""
import collections
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

# Names the docs' C++ snippets use without declaring them (a snippet that declares one itself
# gets no prelude entry for it). Add a row when a doc snippet uses a new free name.
PRELUDE = {
    "scene": "std::unique_ptr<Scene> scene;",
    "error": "Error error;",
    "block": "DeformableActor* block = nullptr;",
    "slide": "Constraint* slide = nullptr;",
    "cursor": "Real3 cursor = Real3::Zero();",
    "controllerPosition": "Real3 controllerPosition = Real3::Zero();",
    "controllerRotation": "Quat controllerRotation = Quat::Identity();",
    "measuredFingerInPalm": "Quat measuredFingerInPalm = Quat::Identity();",
    "i": "int i = 0;",
    "kInf": "constexpr real kInf = std::numeric_limits<real>::infinity();",  # defined in the text
}
for _name in "a b body cabinet drawer forearm hand palm finger handle table".split():
    PRELUDE[_name] = f"RigidActor* {_name} = nullptr;"
HEADERS = "".join(f"#include <{h}>\n"
                  for h in ("superdex/superdex.h", "cmath", "cstdio", "limits", "memory", "string"))
KEYWORDS = {"return", "else", "case", "delete", "throw", "goto", "new", "co_return", "using"}
DECLARATION = re.compile(r"(?:^|[({;]\s*)(?:const\s+)?[A-Za-z_][\w:]*(?:<[^;=()]*>)?(?:\s+const)?"
                         r"(?:\s*[*&]\s*|\s+)([A-Za-z_]\w*)\s*(?:=(?!=)|;|\{)")
REPO_PATH = re.compile(r"^(?:\./)?(?:scripts|examples|perf|tests|docs|python|cmake)/")
PROGRAM = re.compile(r"^(?:\./)?build/(.*/)?(superdex_[\w.-]+)$")
OUTPUT_OPTIONS = {"--out", "--prefix", "-o", "--reference-out"}
SEPARATORS = {";", "&&", "||", "|", "&", "(", ")", ";;"}


def blocks_of(path):
    """(fence line, language, dedented text, trailing spaces stripped) of each fenced block."""
    text = path.read_text()
    return [(text.count("\n", 0, m.start()) + 1, m[1],
             textwrap.dedent(re.sub(r"[ \t]+$", "", m[2], flags=re.M)).rstrip("\n"))
            for m in re.finditer(r"^[ \t]*```([\w+-]*)[ \t]*\n(.*?)^[ \t]*```[ \t]*$", text, re.M | re.S)]


class Checker:
    def __init__(self, root, build):
        self.root, self.build, self.failed = root, build, False
        self.commands = json.loads((build / "compile_commands.json").read_text())
        cache = (build / "CMakeCache.txt").read_text()
        home = re.search(r"^CMAKE_HOME_DIRECTORY:INTERNAL=(.*)$", cache, re.M)
        self.source = Path(home.group(1)) if home else root  # the tree the build compiles
        self.help_texts, self.build_files, self.target_help = {}, None, None
        self.checked = collections.Counter()  # what the current sh block's commands named
        self.results = []  # (file index, fence line, report lines), printed in document order

    def report(self, where, lang, ok, verdict, details=""):
        self.failed |= not ok
        name, line = where.rsplit(":", 1)
        text = [f"{where}  {lang or '-'}  {verdict}"]
        text += ["    " + l for l in (details.strip().splitlines()[:12] if details and not ok else [])]
        self.results.append((self.order[name], int(line), text))

    # ---- C++ -------------------------------------------------------------------------------
    def shown_in(self, text):
        want = [l.strip() for l in text.strip().split("\n")]
        for entry in self.commands:  # compiled files, read from REPO_ROOT (the same tree in ctest)
            rel = os.path.relpath(entry["file"], self.source)
            if rel.split("/")[0] not in ("examples", "tests", "perf") or not (self.root / rel).is_file():
                continue
            have = [l.strip() for l in (self.root / rel).read_text().split("\n")]
            if any(have[k:k + len(want)] == want for k in range(len(have) - len(want) + 1)):
                return rel
        return None

    def compile(self, source):
        entry = next((e for e in self.commands if e["file"].endswith("examples/hello/hello.cpp")), None)
        if entry is None:
            return False, "no compile command for examples/hello/hello.cpp in compile_commands.json"
        args = entry.get("arguments") or shlex.split(entry["command"])
        keep = [a for k, a in enumerate(args)
                if a not in ("-o", "-c", entry["file"]) and args[k - 1] not in ("-o", "-c")]
        with tempfile.NamedTemporaryFile("w", suffix=".cpp", delete=False) as f:
            f.write(source)
        try:
            r = subprocess.run(keep + ["-fsyntax-only", "-x", "c++", f.name], cwd=entry["directory"],
                               capture_output=True, text=True, timeout=600)
        finally:
            os.unlink(f.name)
        return r.returncode == 0, r.stderr

    @staticmethod
    def wrap(where, text, n):
        """(leading #includes, DocBlock<n> with the prelude); #line: errors name the doc's lines."""
        lines = text.split("\n")
        k = 0
        while k < len(lines) and (lines[k].startswith("#include") or not lines[k].strip()):
            k += 1
        body = "\n".join(lines[k:])
        declared = {m.group(1) for l in lines[k:] for m in DECLARATION.finditer(l.strip())} - KEYWORDS
        prelude = [d for name, d in PRELUDE.items()
                   if name not in declared and re.search(rf"\b{name}\b", body)]
        doc, fence = where.rsplit(":", 1)
        return ("\n".join(lines[:k]),
                f"void DocBlock{n}() {{\n  using namespace superdex;\n  " + "\n  ".join(prelude)
                + f'\n#line {int(fence) + 1 + k} "{doc}"\n{body}\n}}\n')

    def check_cpp(self, blocks):
        wrapped = []
        for where, text in blocks:
            source = self.shown_in(text)
            if source:
                self.report(where, "cpp", True, f"ok: shown from {source}")
            elif re.search(r"\bint\s+main\s*\(", text):
                self.report_compile(where, "ok: compiles", *self.compile(text + "\n"))
            else:
                lines = text.count("\n") + 2  # to the closing fence
                wrapped.append((where, lines, self.wrap(where, text, len(wrapped))))
        pending, alone = wrapped, {}
        while pending:  # compiled together; on failure the blocks its diagnostics name (#line) alone
            ok, out = self.compile("\n".join(inc for *_, (inc, _) in pending) + "\n" + HEADERS
                                   + "".join(fn for *_, (_, fn) in pending))
            if ok:
                break
            named = {(m[0], int(m[1])) for m in re.findall(r"^(.+?):(\d+):(?!.*warning:)", out, re.M)}
            suspects = [p for p in pending for doc, fence in [p[0].rsplit(":", 1)]
                        if any(d == doc and 0 < l - int(fence) <= p[1] for d, l in named)] or pending
            for where, _, (inc, fn) in suspects:
                alone[where] = self.compile(inc + "\n" + HEADERS + fn)
            pending = [p for p in pending if p not in suspects]
        for where, *_ in wrapped:
            self.report_compile(where, "ok: compiles (wrapped)", *alone.get(where, (True, "")))

    def report_compile(self, where, verdict, ok, out):
        errors = [l for l in out.splitlines() if "error" in l]
        self.report(where, "cpp", ok, verdict if ok else "FAIL: does not compile", "\n".join(errors or [out]))

    # ---- Python ----------------------------------------------------------------------------
    def check_python(self, name, blocks):
        if not any(re.search(r"^\s*(import|from)\s+mochi\b", t, re.M) for _, t in blocks):
            for where, _ in blocks:
                self.report(where, "python", True, "skipped: the file's python blocks do not import mochi")
            return
        script, starts = "", []
        for _, text in blocks:
            starts.append(script.count("\n") + 1)
            script += text + "\n"
        with tempfile.TemporaryDirectory() as cwd:
            path = Path(cwd) / (name.replace("/", "_") + ".py")
            path.write_text(script)
            env = dict(os.environ, PYTHONPATH=str(self.build / "python"), PYTHONDONTWRITEBYTECODE="1",
                       MPLBACKEND="Agg")
            try:
                r = subprocess.run([sys.executable, str(path)], cwd=cwd, env=env, capture_output=True,
                                   text=True, timeout=120)
                ok, out = r.returncode == 0, r.stderr
            except subprocess.TimeoutExpired:
                ok, out = False, "timed out after 120 s"
        lines = [int(n) for n in re.findall(rf'File "{re.escape(str(path))}", line (\d+)', out)]
        bad = sum(1 for s in starts if s <= lines[-1]) - 1 if lines else len(blocks) - 1
        for k, (where, _) in enumerate(blocks):
            if ok or k < bad:
                self.report(where, "python", True, "ok: ran" + (" (with the blocks above)" if k else ""))
            elif k == bad:
                last = out.strip().splitlines()[-1] if out.strip() else "failed"
                self.report(where, "python", False, f"FAIL: {last}", out)
            else:
                self.report(where, "python", True, "not reached (a block above failed)")

    # ---- sh --------------------------------------------------------------------------------
    def help_of(self, program):
        if program not in self.help_texts:
            try:
                r = subprocess.run([str(program), "--help"], capture_output=True, text=True, timeout=60)
                self.help_texts[program] = r.stdout + r.stderr
            except (OSError, subprocess.TimeoutExpired) as e:
                self.help_texts[program] = f"<{e}>"
        return self.help_texts[program]

    def is_target(self, target):
        if self.build_files is None:
            self.build_files = {f for _, _, files in os.walk(self.build) for f in files}
        if target in self.build_files or any(f.startswith((f"lib{target}.", f"{target}.cpython-"))
                                             for f in self.build_files):
            return True
        if self.target_help is None:
            r = subprocess.run(["cmake", "--build", str(self.build), "--target", "help"],
                               capture_output=True, text=True, timeout=120)
            self.target_help = r.stdout
        return re.search(rf"(?<![\w.-]){re.escape(target)}(?![\w.-])", self.target_help) is not None

    def check_command(self, tokens):
        problems, program, skip_next = [], None, False
        for token in tokens:
            value = token.split("=", 1)[1] if re.match(r"^[A-Za-z_]\w*=", token) else token
            if " " in value:  # a quoted command (bash -c '...'): its paths only
                try:
                    problems += [p for p in self.check_command(shlex.split(value)) if "no such" in p]
                except ValueError:
                    pass
                continue
            if skip_next or "$" in token or any(c in token for c in "*?{"):
                skip_next = False
                continue
            skip_next = token in OUTPUT_OPTIONS
            m = PROGRAM.match(value)
            if m:
                exe = self.build / (m.group(1) or "") / m.group(2)
                self.checked["program"] += 1
                if not (exe.is_file() and os.access(exe, os.X_OK)):
                    problems.append(f"{value}: no such program in {self.build}")
                else:
                    program = exe
            elif REPO_PATH.match(value):
                self.checked["path"] += 1
                if not (self.root / value).exists():
                    problems.append(f"{value}: no such file in the repository")
            elif program and token.startswith("--"):
                option = token.split("=", 1)[0]
                self.checked["option"] += 1
                if not re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", self.help_of(program)):
                    problems.append(f"{option}: not an option of {program.name} (its --help)")
        words = [t for t in tokens if not re.match(r"^[A-Za-z_]\w*=", t)]
        targets = []
        if words[:1] == ["cmake"] and "--build" in words:
            for k, w in enumerate(words):
                if w in ("--target", "-t"):
                    targets += [t for t in words[k + 1:] if not t.startswith("-")][:1]
        elif words[:1] == ["make"] and "-C" in words:  # words but option arguments (-C D, -f F, -j N)
            targets = [w for k, w in enumerate(words[1:]) if not w.startswith("-")
                       and words[k] not in ("-C", "-f") and not (words[k] == "-j" and w.isdigit())]
        self.checked.update(["target"] * len(targets))
        problems += [f"{t}: not a target of the build" for t in targets if not self.is_target(t)]
        return problems

    def check_sh(self, where, text):
        text = re.sub(r"\\\n", " ", text)
        lines = [re.sub(r"\[([^\]]*)\]", lambda m: m.group(1).replace("|", " "), l) for l in text.split("\n")]
        problems, self.checked = [], collections.Counter()
        for line in lines:
            lexer = shlex.shlex(line, posix=True, punctuation_chars=True)
            lexer.commenters, command = "#", []
            try:
                tokens = list(lexer) + [";"]
            except ValueError as e:
                problems.append(f"cannot parse {line!r}: {e}")
                continue
            for token in tokens:
                if token in SEPARATORS:
                    if command:
                        problems += self.check_command(command)
                    command = []
                elif token not in ("do", "then", "else", "done", "fi", "!") or command:
                    command.append(token)
        named = ", ".join(f"{kind}s {n}" for kind, n in sorted(self.checked.items())) or "nothing to check"
        self.report(where, "sh", not problems, "FAIL: " + "; ".join(problems) if problems else f"ok: {named}")

    def run(self):
        files = [self.root / "README.md", *sorted((self.root / "docs").glob("*.md")),
                 self.root / "perf/harness/README.md", *sorted((self.root / "examples").glob("*/README.md")),
                 self.root / "tests/fuzz/README.md"]
        files = [p for p in files if p.exists()]
        self.order = {str(p.relative_to(self.root)): k for k, p in enumerate(files)}
        cpp = []
        for path in files:
            name = str(path.relative_to(self.root))
            python = []
            for line, lang, text in blocks_of(path):
                where = f"{name}:{line}"
                if lang == "cpp":
                    cpp.append((where, text))
                elif lang == "python":
                    python.append((where, text))
                elif lang == "sh":
                    self.check_sh(where, text)
                else:
                    self.report(where, lang, True, "not checked")
            if python:
                self.check_python(name, python)
        self.check_cpp(cpp)
        for *_, text in sorted(self.results):
            print("\n".join(text))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    start = time.monotonic()
    checker = Checker(Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve())
    checker.run()
    print(f"check_doc_blocks: {'FAILED' if checker.failed else 'all blocks ok'} "
          f"({time.monotonic() - start:.0f} s)")
    return 1 if checker.failed else 0


if __name__ == "__main__":
    sys.exit(main())
