#!/usr/bin/env python3
"""A peer's corpus: `shprt scene info` and a tiny `shprt bake` over every model file of Debian's
assimp-testmodels (Assimp's own test corpus, broken files included). CTest test `corpus`.

Each run must end in success (exit 0, no `shprt: error:` line) or in a clean error: exit 1 and
stderr of zero or more `shprt: warning: ...` lines, then exactly one `shprt: error: ...` line,
the last. It must take at most 60 s and leave nothing behind: no output file after a failure,
no temporary (`*.tmp.*`) beside the output or the input, nothing in $TMPDIR. Anything else
(a crash, a hang, a multi-line or unprefixed error, a leftover) is a failure.

Usage: run_corpus.py SHPRT [--models DIR] [--jobs N] [--table FILE.md] [--update-doc docs/corpus.md]
                      [--limit N]
Writes the outcome table by format (extension) to --table; exits 1 on any failure, 77 (CTest
SKIP_RETURN_CODE) when the corpus is not installed. SHPRT_CORPUS_TIMEOUT_S changes the 60 s limit
(for testing this script).
"""
import argparse
import collections
import concurrent.futures
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

# Files in the corpus that are no model: textures, buffers, materials, shaders, notes.
NOT_MODELS = {"png", "jpg", "jpeg", "bmp", "tga", "dds", "bin", "txt", "mtl", "glsl", "vert",
              "frag", "material", "md"}
NOT_MODEL_NAMES = {"README", "LICENSE"}
TIMEOUT_S = int(os.environ.get("SHPRT_CORPUS_TIMEOUT_S", "60"))
WARNING = re.compile(r"^shprt: warning: .+$")
ERROR = re.compile(r"^shprt: error: .+$")


def model_files(root):
    out = []
    for d, _, names in os.walk(root):
        for n in names:
            ext = n.rsplit(".", 1)[1].lower() if "." in n else ""
            if ext in NOT_MODELS or n in NOT_MODEL_NAMES:
                continue
            out.append(os.path.join(d, n))
    return sorted(out)


def extension(path):
    n = os.path.basename(path)
    return n.rsplit(".", 1)[1].lower() if "." in n else "(none)"


def listing(d):
    try:
        return set(os.listdir(d))
    except OSError:
        return set()


def run_one(shprt, model, scratch):
    """Runs both commands on `model`; returns (outcome, detail) with outcome ok | error | FAIL."""
    work = tempfile.mkdtemp(dir=scratch)
    tmp = os.path.join(work, "tmp")
    os.mkdir(tmp)
    env = dict(os.environ, TMPDIR=tmp)
    before = listing(os.path.dirname(model))
    outcomes = []
    for name, args in (("info", ["scene", "info", model]),
                       ("bake", ["bake", model, "-o", os.path.join(work, "out.shprt"),
                                 "--coeffs", "1", "--samples", "8", "--threads", "1"])):
        t0 = time.monotonic()
        # A session of its own, so that a hang is ended with the importer child it may have.
        p = subprocess.Popen([shprt] + args, cwd=work, env=env, stdin=subprocess.DEVNULL,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             start_new_session=True)
        try:
            _, stderr = p.communicate(timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.communicate()
            return "FAIL", f"{name}: no result within {TIMEOUT_S} s"
        seconds = time.monotonic() - t0
        lines = stderr.decode("utf-8", "replace").splitlines()
        if p.returncode == 0:
            if any(not WARNING.match(l) and not l.startswith("shprt: bake: ") for l in lines):
                return "FAIL", f"{name}: exit 0 with stderr {lines!r}"
            outcome = "ok"
        elif p.returncode == 1:
            if not lines or not ERROR.match(lines[-1]) or \
                    not all(WARNING.match(l) for l in lines[:-1]):
                return "FAIL", f"{name}: exit 1 with stderr {lines!r}"
            outcome = "error"
        else:
            return "FAIL", f"{name}: exit code {p.returncode}, stderr {lines[-3:]!r}"
        left = listing(work) - {"tmp"} - ({"out.shprt"} if name == "bake" and outcome == "ok" else set())
        if left:
            return "FAIL", f"{name}: left {sorted(left)} in the working folder"
        if listing(tmp):
            return "FAIL", f"{name}: left {sorted(listing(tmp))} in TMPDIR"
        if listing(os.path.dirname(model)) != before:
            return "FAIL", f"{name}: changed the input's folder: {sorted(listing(os.path.dirname(model)) ^ before)}"
        outcomes.append((outcome, lines[-1] if outcome == "error" else "", seconds))
    shutil.rmtree(work, ignore_errors=True)
    # Both commands ended cleanly: the file is "ok" when both succeeded, else a clean error (a
    # scene may load for `scene info` and still be refused by the bake, e.g. with no area).
    if all(o == "ok" for o, _, _ in outcomes):
        return "ok", ""
    return "error", next(msg for o, msg, _ in outcomes if o == "error")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("shprt")
    ap.add_argument("--models", default="/usr/share/assimp/models")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--table")
    ap.add_argument("--update-doc", help="replace the table under '## Outcomes by extension' "
                    "in this markdown file (docs/corpus.md)")
    ap.add_argument("--limit", type=int, default=0)
    a = ap.parse_args()
    a.shprt = os.path.abspath(a.shprt)
    if not os.path.isdir(a.models):
        print(f"run_corpus: {a.models} is missing (scripts/setup installs assimp-testmodels)")
        return 77
    files = model_files(a.models)
    if a.limit:
        files = files[:a.limit]
    t0 = time.monotonic()
    scratch = tempfile.mkdtemp(prefix="shprt-corpus-")
    results = {}
    try:
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            futures = {pool.submit(run_one, a.shprt, f, scratch): f for f in files}
            for fut in concurrent.futures.as_completed(futures):
                results[futures[fut]] = fut.result()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    seconds = time.monotonic() - t0

    by_ext = collections.defaultdict(collections.Counter)
    failures = []
    for f, (outcome, detail) in sorted(results.items()):
        by_ext[extension(f)][outcome] += 1
        if outcome == "FAIL":
            failures.append(f"{os.path.relpath(f, a.models)}: {detail}")
    total = collections.Counter()
    for c in by_ext.values():
        total.update(c)
    rows = ["| extension | files | ok | clean error | failure |", "|---|---:|---:|---:|---:|"]
    for ext in sorted(by_ext, key=lambda e: (-sum(by_ext[e].values()), e)):
        c = by_ext[ext]
        rows.append(f"| {ext} | {sum(c.values())} | {c['ok']} | {c['error']} | {c['FAIL']} |")
    rows.append(f"| **all** | **{sum(total.values())}** | **{total['ok']}** | "
                f"**{total['error']}** | **{total['FAIL']}** |")
    print("\n".join(rows))
    print(f"run_corpus: {len(files)} files, {a.jobs} workers, {seconds:.1f} s")
    if a.table:
        with open(a.table, "w") as out:
            out.write("<!-- Generated by tests/corpus/run_corpus.py (CTest test `corpus`); "
                      "do not edit. -->\n")
            out.write("\n".join(rows) + "\n")
    if a.update_doc:
        heading = "## Outcomes by extension\n"
        with open(a.update_doc) as f:
            text = f.read()
        text = text[:text.index(heading) + len(heading)]
        with open(a.update_doc, "w") as f:
            f.write(text + "\n" + "\n".join(rows) + "\n")
    for line in failures:
        print("FAIL", line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
