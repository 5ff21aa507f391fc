#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Benchmarks of the wear run (Problem = wear); each appends dated rows to
the table at the end of doc/performance.md and writes its raw output to
benchmarks/results/.

  benchmarks/wear-run.py full    [--prm FILE] [--ranks N]
      The whole run of a parameter file (default prm/iso14243-1.prm, the
      main job, on 2 ranks): wall time, the first block, the blocks that
      update the stiffness and the others, the cost of one contact solve
      broken into mortar coupling, compliance columns, factorisation and
      dense Newton steps, peak memory, mass loss, converged.
  benchmarks/wear-run.py scaling [--mesh medium]
      Three blocks on one rank, on two ranks, and two independent
      one-rank runs at the same time (this machine's own two-process
      throughput): the parallel efficiency against what two cores can do.
  benchmarks/wear-run.py growth [--sizes coarse,medium,fine]
      Two blocks on the coarse, medium and fine TKR A meshes on one rank:
      the cost per contact solve against the number of DoFs, and its
      growth exponent (the fine mesh alone takes over half an hour).

Options: --build DIR (default build/release).
"""
import argparse
import datetime
import math
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The readers of the result files (doc/output.md, "Result files").
sys.path.insert(0, os.path.join(ROOT, "python"))
import tkr_results  # noqa: E402

TABLE_HEADER = """
## Benchmark log (appended by `benchmarks/wear-run.py`)

| date | benchmark | machine | mesh | DoFs | ranks | times | peak memory | result |
|---|---|---|---|---|---|---|---|---|
"""


def machine():
    model = ""
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return f"{os.cpu_count()} cores, {model}"


def make_prm(base, directory, mesh=None, cycles=None):
    """A copy of @p base with the output directory (and mesh, cycles)
    replaced."""
    with open(os.path.join(ROOT, base)) as f:
        text = f.read()
    text = re.sub(r"(?m)^(\s*set Directory\s*=).*$", rf"\1 {directory}", text)
    if mesh:
        text = re.sub(r"(?m)^(\s*set File\s*=).*$", rf"\1 {mesh}", text)
    if cycles:
        text = re.sub(r"(?m)^(\s*set Cycles\s*=).*$", rf"\1 {cycles:g}", text)
    text += "\nsubsection Output\n  set Plots = false\nend\n"
    handle, name = tempfile.mkstemp(suffix=".prm")
    with os.fdopen(handle, "w") as f:
        f.write(text)
    return name


def start(build, prm, ranks, log):
    env = dict(os.environ)
    if os.geteuid() == 0:
        env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
        env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    command = ["/usr/bin/time", "-f", "peak RSS %M kB"]
    if ranks > 1:
        command += ["mpirun", "-np", str(ranks)]
    command += [os.path.join(build, "tkr-wear"), prm]
    out = open(log, "w")
    return subprocess.Popen(command, cwd=ROOT, env=env, stdout=out, stderr=subprocess.STDOUT), out


def finish(process, out, directory, log):
    """Wait for a run and collect its numbers."""
    process.wait()
    out.close()
    with open(log) as f:
        text = f.read()
    if process.returncode != 0:
        sys.exit(f"the run failed (exit {process.returncode}); see {log}")
    summary = tkr_results.read_summary(os.path.join(directory, "summary.json"))
    blocks = [float(t) for t in re.findall(r"^Block .*?([0-9.]+) s/block", text, re.M)]
    first = re.search(r"contact solves: (\d+)", text)
    timers = {
        m.group(1).strip(): (int(m.group(2)), float(m.group(3)))
        for m in re.finditer(r"^\| ([a-z][a-zA-Z /-]*?)\s*\|\s*(\d+) \|\s*([0-9.e+-]+)s \|", text, re.M)
    }
    rss = [int(m) for m in re.findall(r"peak RSS (\d+) kB", text)]
    return {
        "summary": summary,
        "blocks": blocks,
        "first_solves": int(first.group(1)) if first else 0,
        "timers": timers,
        "peak_rss_mb": max(rss) / 1024 if rss else 0,
        "log": log,
    }


def run(build, prm, ranks, tag):
    directory = tempfile.mkdtemp(prefix=f"tkr-bench-{tag}-")
    name = make_prm(prm["base"], directory, prm.get("mesh"), prm.get("cycles"))
    log = os.path.join(
        ROOT, "benchmarks", "results", f"wear-run-{tag}-{datetime.datetime.now():%Y%m%d-%H%M%S}.txt"
    )
    process, out = start(build, name, ranks, log)
    result = finish(process, out, directory, log)
    os.unlink(name)
    return result


def per_solve(r):
    """Seconds per contact solve in the blocks after the first (warm)."""
    solves = r["summary"]["contact_solves"] - r["first_solves"]
    return sum(r["blocks"][1:]) / solves if solves > 0 else float("nan")


def append_rows(rows):
    path = os.path.join(ROOT, "doc", "performance.md")
    with open(path) as f:
        text = f.read()
    if "## Benchmark log" not in text:
        text = text.rstrip("\n") + "\n" + TABLE_HEADER
    text = text.rstrip("\n") + "\n" + "\n".join(rows) + "\n"
    with open(path, "w") as f:
        f.write(text)
    print("\n".join(rows))
    print(f"appended to {path}")


def row(benchmark, mesh, r, ranks, times, result):
    s = r["summary"]
    return (
        f"| {datetime.date.today()} | {benchmark} | {machine()} | {mesh} "
        f"| {s['dofs']:,} | {ranks} | {times} "
        f"| {r['peak_rss_mb']:.0f} MB per process | {result} |"
    )


def result_text(s):
    return (
        f"{s['cycles']:g} cycles in {s['blocks']} blocks, "
        f"mass loss {s['mass_loss_mg']:.6g} mg, "
        f"converged {str(s['converged']).lower()}"
    )


def full(args):
    r = run(args.build, {"base": args.prm}, args.ranks, "full")
    s, blocks, t = r["summary"], r["blocks"], r["timers"]
    interval = s["stiffness_update_interval"]
    update = [b for i, b in enumerate(blocks[1:], start=1) if interval > 0 and i % interval == 0]
    other = [b for i, b in enumerate(blocks[1:], start=1) if not (interval > 0 and i % interval == 0)]
    solves = s["contact_solves"]

    def section(name):
        calls, wall = t.get(name, (0, 0.0))
        return f"{name} {wall:.1f} s ({calls})"

    times = (
        f"**{s['wall_time_s']:.0f} s** in all; first block {blocks[0]:.1f} s"
        + (f", {len(update)} stiffness updates {sum(update) / len(update):.1f} s each" if update else "")
        + (f", other blocks {sum(other) / len(other):.2f} s each" if other else "")
        + f"; {solves} contact solves, {1e3 * per_solve(r):.1f} ms per warm solve"
        + " (rank 0: "
        + ", ".join(
            section(n)
            for n in [
                "mortar coupling",
                "compliance columns",
                "direct factorisation",
                "condensed Newton step",
                "output",
            ]
        )
        + ")"
    )
    with open(os.path.join(ROOT, args.prm)) as f:
        mesh = re.search(r"(?m)^\s*set File\s*=\s*(\S+)", f.read())
    mesh = os.path.basename(mesh.group(1)) if mesh else "default mesh"
    append_rows([row(f"full run `{args.prm}`", mesh, r, args.ranks, times, result_text(s))])


def scaling(args):
    prm = {"base": "prm/iso14243-1.prm", "mesh": f"meshes/tkr/tkr-a-{args.mesh}.msh", "cycles": 1.5e5}
    one = run(args.build, prm, 1, "scaling-1")
    two = run(args.build, prm, 2, "scaling-2")
    # Two independent one-rank runs at once.
    pair = []
    for i in range(2):
        directory = tempfile.mkdtemp(prefix=f"tkr-bench-pair{i}-")
        name = make_prm(prm["base"], directory, prm["mesh"], prm["cycles"])
        log = os.path.join(
            ROOT,
            "benchmarks",
            "results",
            f"wear-run-scaling-pair{i}-{datetime.datetime.now():%Y%m%d-%H%M%S}.txt",
        )
        pair.append((start(args.build, name, 1, log), directory, log, name))
    pair_results = []
    for (process, out), directory, log, name in pair:
        pair_results.append(finish(process, out, directory, log))
        os.unlink(name)
    t1 = one["summary"]["wall_time_s"]
    t2 = two["summary"]["wall_time_s"]
    tp = max(p["summary"]["wall_time_s"] for p in pair_results)
    times = (
        f"1 rank {t1:.1f} s; 2 ranks {t2:.1f} s (speed-up {t1 / t2:.2f}); "
        f"two 1-rank runs at once {tp:.1f} s each; "
        f"efficiency against that throughput {tp / (2 * t2):.2f}"
    )
    same = (
        abs(one["summary"]["mass_loss_mg"] - two["summary"]["mass_loss_mg"])
        <= 1e-10 * one["summary"]["mass_loss_mg"]
    )
    append_rows(
        [
            row(
                "scaling (3 blocks)",
                os.path.basename(prm["mesh"]),
                two,
                "1, 2",
                times,
                result_text(two["summary"]) + f"; 1 and 2 ranks {'agree' if same else 'DIFFER'}",
            )
        ]
    )


def growth(args):
    results = []
    for size in args.sizes.split(","):
        prm = {"base": "prm/iso14243-1.prm", "mesh": f"meshes/tkr/tkr-a-{size}.msh", "cycles": 1e5}
        r = run(args.build, prm, 1, f"growth-{size}")
        results.append((size, r))
    rows = []
    n0, t0 = results[0][1]["summary"]["dofs"], per_solve(results[0][1])
    b0 = results[0][1]["blocks"][0]
    for size, r in results:
        n, t, b = r["summary"]["dofs"], per_solve(r), r["blocks"][0]
        exponent = (
            ""
            if n == n0
            else f"; exponent against coarse: per solve "
            f"{math.log(t / t0) / math.log(n / n0):.2f}, first block "
            f"{math.log(b / b0) / math.log(n / n0):.2f}"
        )
        times = (
            f"{1e3 * t:.1f} ms per warm contact solve; first block "
            f"{b:.1f} s ({r['first_solves']} solves){exponent}"
        )
        rows.append(row("growth (2 blocks)", f"tkr-a-{size}.msh", r, 1, times, result_text(r["summary"])))
    append_rows(rows)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("benchmark", choices=["full", "scaling", "growth"])
    parser.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    parser.add_argument("--prm", default="prm/iso14243-1.prm")
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--mesh", default="medium")
    parser.add_argument(
        "--sizes", default="coarse,medium,fine", help="growth: the TKR A meshes, coarse first"
    )
    args = parser.parse_args()
    os.makedirs(os.path.join(ROOT, "benchmarks", "results"), exist_ok=True)
    if not os.path.exists(os.path.join(args.build, "tkr-wear")):
        sys.exit(f"no tkr-wear in {args.build}: build it first " "(scripts/run-main-job or cmake)")
    started = time.time()
    {"full": full, "scaling": scaling, "growth": growth}[args.benchmark](args)
    print(f"benchmark took {time.time() - started:.0f} s")


if __name__ == "__main__":
    try:
        main()
    except tkr_results.ResultError as e:  # a summary.json not as documented
        sys.exit(f"wear-run.py: error: {e}")
