"""Checks that README.md shows the hello worlds exactly as examples/hello/ has them (ctest
readme_examples; ctest hello_cpp and hello_python run the files), so that the first
screen's code cannot drift from code that compiles and runs.

usage: check_readme_examples.py REPOSITORY_ROOT"""
import re
import sys
from pathlib import Path


def main():
    root = Path(sys.argv[1])
    readme = (root / "README.md").read_text()
    blocks = re.findall(r"```(\w*)\n(.*?)```", readme, re.S)
    status = 0
    for name, language in (("hello.cpp", "cpp"), ("hello.py", "python")):
        text = (root / "examples" / "hello" / name).read_text()
        if not any(lang == language and body == text for lang, body in blocks):
            print(f"check_readme_examples: README.md has no ```{language} block equal to examples/hello/{name}")
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
