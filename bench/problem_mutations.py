#!/usr/bin/python3
"""Mutation campaign on sage solve's problem files (issue 39's acceptance check).

Seeds: the bundled problems (examples/problems/*.json). Each mutant replaces
one number or formula of a seed (anywhere: data, boundary conditions, the
inline domain model) by a value a user gets wrong: 0, -1, 1/0, log(0), nan,
huge and tiny numbers, formulas that change sign inside the domain. Every
mutant is solved on a coarse grid (the checks do not depend on it), and the
campaign counts crashes (a signal or an exit code other than 0, 1, 2), runs
longer than the time limit, and failures whose message does not name the
mutated key (its JSON pointer, or the key's name; a mutated array entry
counts as named by its array's key). A refusal that names the consequence
instead (the domain is empty, the grid too coarse for it) is listed as
"unnamed" for the reader to judge.

Usage: bench/problem_mutations.py SAGE [MUTANTS] [WORKERS] [SEED]
       (defaults: 10000 mutants, 2 workers, seed 1); prints a summary and the
       first cases of each kind of finding.
"""
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEEDS = os.path.join(ROOT, "examples", "problems")
TIME_LIMIT = 10.0
REPLACEMENTS = [0, -1, "1/0", "log(0)", "nan", "sqrt(-1)", 1e308, -1e308, 1e-308, 1e30, "x", "y - 0.3",
                "sin(40*x)", "-x*y", "1/x", "exp(1000*x)", "0*x"]


def leaves(node, pointer=""):
    """Every number or string leaf of a JSON value with its pointer."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from leaves(value, pointer + "/" + key.replace("~", "~0").replace("/", "~1"))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from leaves(value, pointer + "/" + str(i))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield pointer
    elif isinstance(node, str) and pointer.rsplit("/", 1)[-1] not in ("name", "description", "type", "physics",
                                                                     "primitive", "op", "robin", "plane", "domain"):
        yield pointer


def key_name(pointer):
    """The mutated key's name: the pointer's last token that is not an array index."""
    return next(token for token in reversed(pointer.split("/")) if not token.isdigit())


def replaced(node, pointer, value):
    copy = json.loads(json.dumps(node))
    parts = [p.replace("~1", "/").replace("~0", "~") for p in pointer.split("/")[1:]]
    target = copy
    for p in parts[:-1]:
        target = target[int(p)] if isinstance(target, list) else target[p]
    last = parts[-1]
    if isinstance(target, list):
        target[int(last)] = value
    else:
        target[last] = value
    return copy


def main():
    sage = sys.argv[1]
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 10000
    workers = int(sys.argv[3]) if len(sys.argv) > 3 else 2
    rng = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    seeds = []
    for name in sorted(os.listdir(SEEDS)):
        if name.endswith(".json"):
            with open(os.path.join(SEEDS, name)) as f:
                problem = json.load(f)
            if isinstance(problem.get("domain"), str):  # a model path: make it absolute
                problem["domain"] = os.path.normpath(os.path.join(SEEDS, problem["domain"]))
            seeds.append((name, problem, list(leaves(problem))))
    work = tempfile.mkdtemp(prefix="sage_mutations_")
    mutants = []
    for i in range(count):
        name, problem, pointers = rng.choice(seeds)
        pointer = rng.choice(pointers)
        value = rng.choice(REPLACEMENTS)
        if value == "nan":
            value = float("nan")
        path = os.path.join(work, "m%05d.json" % i)
        with open(path, "w") as f:
            json.dump(replaced(problem, pointer, value), f)
        mutants.append((i, name, pointer, value, path))

    def run(mutant):
        i, name, pointer, value, path = mutant
        three_d = (name.startswith(("bracket_3d", "ball", "block")))
        out = os.path.join(work, "m%05d.vtu" % i)
        start = time.monotonic()
        try:
            r = subprocess.run([sage, "solve", path, "-o", out, "--cells", "8" if three_d else "16", "-q"],
                               capture_output=True, text=True, timeout=60)
            code, message = r.returncode, r.stdout + r.stderr
        except subprocess.TimeoutExpired:
            code, message = "timeout", ""
        seconds = time.monotonic() - start
        for p in (path, out):
            if os.path.exists(p):
                os.remove(p)
        return i, name, pointer, value, code, seconds, message

    start = time.monotonic()
    with ThreadPoolExecutor(workers) as pool:
        results = list(pool.map(run, mutants))
    os.rmdir(work)
    crashes = [r for r in results if r[4] not in (0, 1, 2)]
    slow = [r for r in results if r[5] > TIME_LIMIT and r[4] != 0]
    failed = [r for r in results if r[4] in (1, 2)]
    unnamed = [r for r in failed if r[2] not in r[6] and key_name(r[2]) not in r[6]]
    # JSON has no NaN: such a mutant is malformed JSON, named by line and column.
    malformed = [r for r in unnamed if "malformed JSON" in r[6]]
    geometry = [r for r in unnamed if r not in malformed and r[2].startswith(("/domain", "/bounds"))]
    unnamed = [r for r in unnamed if r not in malformed and r not in geometry]
    print("%d mutants of %d seeds, %.0f s with %d workers" % (len(results), len(seeds), time.monotonic() - start,
                                                            workers))
    print("  solved (exit 0): %d; refused (exit 1 or 2): %d" % (len(results) - len(failed) - len(crashes),
                                                               len(failed)))
    print("  crashes: %d; refused after more than %g s: %d; refusals not naming the key: %d" % (
        len(crashes), TIME_LIMIT, len(slow), len(unnamed)))
    print("  refusals naming a line and column of malformed JSON (NaN mutants): %d; refusals of geometry mutants "
          "naming the consequence (empty domain, grid too coarse, a part's field): %d" % (len(malformed), len(geometry)))
    print("  slowest refusal %.2f s, slowest run %.2f s" % (max([r[5] for r in failed] or [0]),
                                                          max(r[5] for r in results)))
    for title, cases in (("crash", crashes), ("slow", slow), ("unnamed", unnamed), ("geometry", geometry[:3])):
        for i, name, pointer, value, code, seconds, message in cases[:10]:
            print("%s: %s %s = %r: exit %s, %.1f s: %s" % (title, name, pointer, value, code, seconds,
                                                          message.strip().splitlines()[-1:] if message else ""))
    return 1 if crashes or slow or unnamed else 0  # geometry consequences are listed for the reader to judge


if __name__ == "__main__":
    sys.exit(main())
