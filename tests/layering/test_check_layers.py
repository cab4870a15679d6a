#!/usr/bin/env python3
"""Self-test of scripts/check_layers.py: it passes a clean tree and fails,
naming the include, on each kind of violation.

Each test builds a small fake repository in a temporary folder (a
docs/architecture.md with a Layers section, a few folders and files) and
checks it. Standard library only: python3 tests/layering/test_check_layers.py
"""
import importlib.util
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

sys.dont_write_bytecode = True  # no __pycache__ in scripts/
SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "check_layers.py"
_spec = importlib.util.spec_from_file_location("check_layers", SCRIPT)
check_layers = importlib.util.module_from_spec(_spec)
sys.modules["check_layers"] = check_layers  # dataclasses look their module up
_spec.loader.exec_module(check_layers)

LAYERS_SECTION = """\
## Layers

Lowest first; an arrow never points up.

Layer order: core → linsolve → assembly → stage → actors → constraints → contact → solver → scene → superdex.h

Above the library, through installed headers only: perf, examples, python

perf/ may also include: core/mpi.h, actors/tet_element.h
"""

ARCHITECTURE = "# Architecture\n\n## One step\n\nText.\n\n" + LAYERS_SECTION + "\n## Next\n\nMore.\n"

# A clean tree: stage/, contact/ and solver/ are missing on purpose.
CLEAN_TREE = {
    "docs/architecture.md": ARCHITECTURE,
    "core/types.h": "#pragma once\n#include <vector>\n",
    "core/mpi.h": "#pragma once\n#include <superdex/core/types.h>\n",
    "linsolve/linear_solver.h": "#pragma once\n#include <superdex/core/types.h>\n",
    "actors/tet_element.h": "#pragma once\n#include <superdex/core/types.h>\n",
    "actors/actor.h": "#pragma once\n#include <superdex/core/types.h>\n#include \"tet_element.h\"\n",
    "actors/actor.cc": "#include <superdex/actors/actor.h>\n#include <superdex/linsolve/linear_solver.h>\n",
    "scene/scene.h": "#pragma once\n#include <superdex/actors/actor.h>\n",
    "superdex.h": "#pragma once\n#include <superdex/core/types.h>\n#include <superdex/scene/scene.h>\n",
    "perf/harness/run.h": "#pragma once\n#include <superdex/superdex.h>\n",
    "perf/harness/run.cc": "#include \"run.h\"\n#include <superdex/core/mpi.h>\n",
    "perf/tet/tet.cpp": "#include <superdex/actors/tet_element.h>\n",
    "examples/demo/main.cpp": "#include <superdex/superdex.h>\n#include \"../common/util.h\"\n",
    "examples/common/util.h": "#pragma once\n#include <superdex/superdex.h>\n",
    "python/src/module.cpp": "#include <superdex/superdex.h>\n#include \"defines.h\"\n",
    # exempt: tests and scripts include anything
    "tests/white_box.cc": "#include <superdex/actors/actor.h>\n#include <superdex/core/mpi.h>\n",
    "scripts/tool.cpp": "#include <superdex/scene/scene.h>\n",
}


class CheckLayersTest(unittest.TestCase):
    def setUp(self):
        self.root = Path(tempfile.mkdtemp(prefix="check_layers_"))
        self.addCleanup(shutil.rmtree, self.root)
        self.write(CLEAN_TREE)

    def write(self, files):
        for path, text in files.items():
            (self.root / path).parent.mkdir(parents=True, exist_ok=True)
            (self.root / path).write_text(text, encoding="utf-8")

    def violations(self):
        return check_layers.check_tree(self.root).violations

    def assert_one_violation_naming(self, *parts):
        found = [v for v in self.violations() if all(part in v for part in parts)]
        self.assertTrue(found, f"no violation names {parts}: {self.violations()}")

    def run_script(self):
        return subprocess.run([sys.executable, str(SCRIPT), str(self.root)],
                              capture_output=True, text=True)

    def test_clean_tree_passes(self):
        self.assertEqual(self.violations(), [])
        result = self.run_script()
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertRegex(result.stdout, r"^check_layers: OK \(\d+ files, \d+ includes\)\n$")

    def test_upward_include_fails_and_is_named(self):
        self.write({"actors/rigid_actor.h":
                    "#pragma once\n\n#include <superdex/scene/scene.h>\n"})
        self.assertIn("actors/rigid_actor.h:3 includes scene/scene.h: "
                      "actors (layer 4) may not include scene (layer 8)", self.violations())
        result = self.run_script()
        self.assertEqual(result.returncode, 1)
        self.assertIn("actors/rigid_actor.h:3 includes scene/scene.h", result.stdout)

    def test_upward_include_to_umbrella_fails(self):
        self.write({"core/bad.h": "#include <superdex/superdex.h>\n"})
        self.assert_one_violation_naming("core/bad.h:1", "may not include superdex.h (layer 9)")

    def test_upward_quoted_include_fails(self):
        self.write({"core/bad.cc": "#include \"../scene/scene.h\"\n"})
        self.assert_one_violation_naming("core/bad.cc:1 includes scene/scene.h",
                                         "core (layer 0) may not include scene")

    def test_library_including_a_file_outside_it_fails(self):
        self.write({"scene/bad.cc": "#include \"../perf/harness/run.h\"\n",
                    "actors/bad.cc": "#include <superdex/tests/white_box.h>\n"})
        self.assert_one_violation_naming("scene/bad.cc:1 includes perf/harness/run.h",
                                         "outside the library")
        self.assert_one_violation_naming("actors/bad.cc:1 includes tests/white_box.h",
                                         "in no layer")

    def test_folder_cycle_fails(self):
        self.write({"core/bad.h": "#include <superdex/actors/actor.h>\n"})
        self.assert_one_violation_naming("folder cycle: actors → core → actors")

    def test_file_cycle_within_a_folder_fails(self):
        self.write({"core/a.h": "#pragma once\n#include <superdex/core/b.h>\n",
                    "core/b.h": "#pragma once\n#include \"c.h\"\n",
                    "core/c.h": "#pragma once\n#include <superdex/core/a.h>\n"})
        self.assert_one_violation_naming("file cycle: core/a.h → core/b.h → core/c.h → core/a.h")
        self.assertEqual(len(self.violations()), 1, self.violations())

    def test_file_cycle_above_the_library_fails(self):
        self.write({"perf/harness/run.h": "#pragma once\n#include \"run.cc\"\n"})
        self.assert_one_violation_naming("file cycle: perf/harness/run.cc → perf/harness/run.h")

    def test_perf_including_an_unlisted_internal_header_fails(self):
        self.write({"perf/bench/bench.cpp":
                    "#include <superdex/core/mpi.h>\n#include <superdex/linsolve/linear_solver.h>\n"})
        found = [v for v in self.violations() if v.startswith("perf/bench/bench.cpp")]
        self.assertEqual(len(found), 1, self.violations())
        self.assertIn("perf/bench/bench.cpp:2 includes linsolve/linear_solver.h", found[0])

    def test_examples_and_python_may_include_only_the_umbrella(self):
        self.write({"examples/demo/extra.cpp": "#include <superdex/core/mpi.h>\n",
                    "python/src/extra.cpp": "#include <superdex/actors/tet_element.h>\n"})
        self.assert_one_violation_naming("examples/demo/extra.cpp:1 includes core/mpi.h")
        self.assert_one_violation_naming("python/src/extra.cpp:1 includes actors/tet_element.h")

    def test_relative_include_into_the_library_from_above_fails(self):
        self.write({"examples/demo/sneaky.cpp": "#include \"../../core/types.h\"\n"})
        self.assert_one_violation_naming("examples/demo/sneaky.cpp:1 includes core/types.h",
                                         "by a relative path")

    def test_missing_layers_section_fails(self):
        self.write({"docs/architecture.md": "# Architecture\n\n## One step\n\nText.\n"})
        with self.assertRaises(check_layers.LayerSpecError):
            check_layers.check_tree(self.root)
        result = self.run_script()
        self.assertEqual(result.returncode, 2)
        self.assertIn("no section '## Layers'", result.stderr)

    def test_layers_section_without_order_line_fails(self):
        self.write({"docs/architecture.md":
                    ARCHITECTURE.replace("Layer order:", "The order:")})
        with self.assertRaisesRegex(check_layers.LayerSpecError, "Layer order"):
            check_layers.check_tree(self.root)

    def test_build_folders_are_skipped(self):
        self.write({"python/build/generated.cpp": "#include <superdex/core/mpi.h>\n",
                    "build/actors/x.h": "#include <superdex/scene/scene.h>\n"})
        self.assertEqual(self.violations(), [])

    @unittest.skipUnless(shutil.which("git"), "git not installed")
    def test_in_a_git_checkout_only_tracked_files_count(self):
        subprocess.run(["git", "init", "-q", str(self.root)], check=True)
        subprocess.run(["git", "-C", str(self.root), "add", "."], check=True)
        self.write({"actors/untracked.h": "#include <superdex/scene/scene.h>\n"})
        self.assertEqual(self.violations(), [])
        subprocess.run(["git", "-C", str(self.root), "add", "actors/untracked.h"], check=True)
        self.assert_one_violation_naming("actors/untracked.h:1 includes scene/scene.h")


if __name__ == "__main__":
    unittest.main()
