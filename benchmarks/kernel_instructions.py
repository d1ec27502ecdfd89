"""The machine code of every compiled kernel function, counted in x86 instructions.

Wall and even CPU time on a shared machine scatter by tens of per cent from run to run; the
code the compiler makes does not. This script compiles the kernels afresh (a temporary
``NUMBA_CACHE_DIR``) for one CPU model (``NUMBA_CPU_NAME``, default ``haswell``; the
features are the host's, so compare two versions on one machine), by simulating a short
rubbing run of the study's case 1 on the full and on the reduced model, then counts the
instructions of every compiled signature of every Numba function in ``rubdiag._kernels``.
Two versions of rubdiag whose counts are equal function by function run the same
instructions: what their timings differ by is the machine.

Usage::

    # in each checkout (or with PYTHONPATH=<checkout>), then compare
    .venv/bin/python benchmarks/kernel_instructions.py --json a.json
    .venv/bin/python benchmarks/kernel_instructions.py --compare a.json b.json

A function inlined into its caller (``inline="always"``) has no code of its own and is not
listed; its instructions count in the caller's.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import pkgutil
import re
import sys
import tempfile
from pathlib import Path

#: a line of assembly that is an instruction: indented, a mnemonic, not a directive (".p2align")
INSTRUCTION = re.compile(r"^\s+[a-z][a-z0-9]*(\s|$)")


def compile_kernels() -> None:
    """Simulate 0.32 s of case 1 at its serious gap (10-ms gap ramp) on the full and the
    reduced model: every kernel a rubbing run uses is compiled for the arrays it gets."""
    from rubdiag.reduce import Reduction
    from rubdiag.simulation import Run, simulate

    for reduction in (None, Reduction()):
        simulate(Run.paper_case(1, 1.9, duration_s=0.32, discard_s=0.3, gap_ramp_s=0.01,
                                reduction=reduction))


def instruction_counts() -> dict[str, int]:
    """``{"module.function[signature]": instructions}`` for every compiled kernel."""
    import numba

    import rubdiag._kernels as kernels

    counts = {}
    for info in pkgutil.iter_modules(kernels.__path__, "rubdiag._kernels."):
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            if not isinstance(value, numba.core.registry.CPUDispatcher):
                continue
            if value.__module__ != module.__name__:
                continue            # imported from another kernel module: counted there
            for signature in value.signatures:
                asm = value.inspect_asm(signature)
                key = f"{info.name.rsplit('.', 1)[1]}.{name}[{len(signature)} args]"
                counts[key] = sum(1 for line in asm.splitlines() if INSTRUCTION.match(line))
    return counts


def compare(a: dict[str, int], b: dict[str, int]) -> int:
    """Print the functions side by side; returns the number that differ or are in one only.
    Functions are matched by name, without their module and leading underscores: a function
    that moved to another kernel module or became a module's public name is still itself
    (several functions of one name are compared as the sorted list of their counts)."""
    def by_name(counts):
        names = {}
        for key, n in counts.items():
            names.setdefault(key.split(".", 1)[1].lstrip("_"), []).append(n)
        return {name: found[0] if len(found) == 1 else tuple(sorted(found))
                for name, found in names.items()}

    na, nb = by_name(a), by_name(b)
    differ = 0
    print(f"{'function':<52} {'A':>8} {'B':>8}")
    for name in sorted(set(na) | set(nb)):
        ca, cb = na.get(name), nb.get(name)
        mark = "" if ca == cb else "  <- differs"
        differ += ca != cb
        print(f"{name:<52} {ca if ca is not None else '—':>8} "
              f"{cb if cb is not None else '—':>8}{mark}")
    same = sum(1 for name in set(na) & set(nb) if na[name] == nb[name])
    total = [sum(counts.values()) for counts in (a, b)]
    print(f"\n{same} functions with the same instruction count; {differ} differ or are in "
          f"one version only; A total {total[0]}, B total {total[1]}")
    return differ


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", type=Path, help="write the counts here")
    ap.add_argument("--compare", nargs=2, type=Path, metavar=("A", "B"),
                    help="compare two files this script wrote, and stop")
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.loads(p.read_text(encoding="utf-8"))["counts"] for p in args.compare)
        return 1 if compare(a, b) else 0
    if os.environ.get("NUMBA_CACHE_DIR") is None:
        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="rubdiag-asm-")
    os.environ.setdefault("NUMBA_CPU_NAME", "haswell")
    import rubdiag

    rubdiag.pin_blas_kernels()
    compile_kernels()
    counts = instruction_counts()
    for key, n in sorted(counts.items()):
        print(f"{key:<60} {n:>8}")
    print(f"{len(counts)} compiled functions, {sum(counts.values())} instructions "
          f"(NUMBA_CPU_NAME={os.environ['NUMBA_CPU_NAME']}; rubdiag from "
          f"{Path(rubdiag.__file__).parent.parent})")
    if args.json is not None:
        args.json.write_text(json.dumps({"cpu": os.environ["NUMBA_CPU_NAME"],
                                         "counts": counts}, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
