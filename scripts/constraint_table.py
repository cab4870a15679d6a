"""The table of constraint types in docs/constraints.md, made from the list.

Every constraint type is one line of constraints/constraint_types.h; mochi
binds each from that line (ConstraintType.<Name>, <Name>ConstraintParams with
its fields and summary, Scene.create_<name>_constraint). This script reads
them back from the built module and writes the table between the markers
<!-- constraint-types:begin --> and <!-- constraint-types:end -->, so the
docs list exactly the types the library has.

usage (Debian's python3 with the build's module on the path):
  PYTHONPATH=build/python /usr/bin/python3 scripts/constraint_table.py --check docs/constraints.md
  PYTHONPATH=build/python /usr/bin/python3 scripts/constraint_table.py --write docs/constraints.md
  PYTHONPATH=build/python /usr/bin/python3 scripts/constraint_table.py          (prints the table)
--check exits 1 when the page's table differs from the list (and prints the
expected one); --write replaces it.
"""
import re
import sys

import mochi

BEGIN = "<!-- constraint-types:begin -->"
END = "<!-- constraint-types:end -->"
COMPLIANT = ("stiffness", "damping", "saturation")


def snake(name):
    return re.sub(r"(?<=[a-z])(?=[A-Z0-9])|(?<=[0-9])(?=[A-Z])", "_", name).lower()


def camel(field):
    head, *rest = field.split("_")
    return head + "".join(part[:1].upper() + part[1:] for part in rest)


def fields(params_class):
    # the properties mochi binds from the params struct's Fields(), in order
    return [name for name, value in vars(params_class).items() if isinstance(value, property)]


def table():
    rows = [
        "| Type | Factory | mochi | Fields (besides stiffness, damping, saturation) | Summary |",
        "|---|---|---|---|---|",
    ]
    for name in mochi.ConstraintType.__members__:
        params = getattr(mochi, name + "ConstraintParams")
        factory = "create_" + snake(name) + "_constraint"
        if not hasattr(mochi.Scene, factory):
            raise SystemExit(f"constraint_table: mochi.Scene has no {factory} for ConstraintType.{name}")
        own = ", ".join(f"`{camel(f)}`" for f in fields(params) if f not in COMPLIANT)
        summary = (params.__doc__ or "").strip().splitlines()[0] if params.__doc__ else ""
        rows.append(f"| {name} | `Create{name}Constraint` | `{factory}` | {own} | {summary} |")
    return "\n".join(rows) + "\n"


def main():
    args = sys.argv[1:]
    generated = table()
    if not args:
        sys.stdout.write(generated)
        return 0
    mode, path = args
    text = open(path, encoding="utf-8").read()
    match = re.search(re.escape(BEGIN) + r"\n(.*?)" + re.escape(END), text, re.S)
    if not match:
        print(f"constraint_table: {path} has no {BEGIN} ... {END} block")
        return 1
    if mode == "--check":
        if match.group(1) == generated:
            print(f"constraint_table: {path} lists the {len(mochi.ConstraintType.__members__)} types of the list")
            return 0
        print(f"constraint_table: the table in {path} differs from the list; expected:\n{generated}")
        print("(regenerate with scripts/constraint_table.py --write)")
        return 1
    if mode == "--write":
        text = text[: match.start(1)] + generated + text[match.end(1):]
        open(path, "w", encoding="utf-8").write(text)
        return 0
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main())
