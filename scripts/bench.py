#!/usr/bin/env python3
"""`make bench`: the harness's speed measured side by side, every figure a ratio with its spread.

Run it through the Makefile (`make bench`, or `make bench BASELINE=<commit>`), which builds the
baseline's binary beside the working tree's (scripts/bench_baseline.sh) and then calls

    python3 scripts/bench.py --current target/release/signorini \\
        --baseline target/bench-baseline/<commit>/signorini --baseline-commit <commit> \\
        [--repeats 5] [--fine] [--out reports]

It solves no discrete problem of its own: it runs `signorini` commands (the step kernels of the
1D Dirichlet bar at NX = 640, the Tables 1–2 study, the 3D bar's runs at levels 80 and 160; with
--fine also a round-off sensitivity study of 4 members and the 3D level-320 run) with two
binaries in alternation, in one go, and measures each process's CPU time (user + system, from
wait4) and peak resident size.

* **Against the baseline**: each figure is run `repeats` times by each binary, in the order
  baseline, working tree, then working tree, baseline, and so on (ABBA), so that a drift of the
  machine's speed falls on both sides alike. Each pair gives a ratio working tree / baseline;
  the figure is the median of the ratios, and its interval the range of the ratios: for the
  median of a distribution it is a distribution-free confidence interval of level
  1 − 2^(1−n) for n pairs (94 % for 5, 98 % for 7). A ratio is a **regression** when its whole
  interval lies above 1.10, **ok** when it lies at or below 1.10, **undecided** otherwise.
* **What the checks cost**: the working tree's binary run with its per-step checks (non-finite
  values, energy balance, physics monitor) on and off (the benchmark's internal switch,
  SIGNORINI_BENCHMARK_CHECKS=off, src/harness/run/driver.rs), in alternation as above: the
  ratio on / off of the 1D run (Crank–Nicolson, redistributed mass, NX = 640) must be at most
  1.05 and of the 3D level-80 run at most 1.03, decided by the interval the same way.
* **Absolute figures** (ns per dof-step of CPU time, seconds, MB) are printed for the working
  tree with the range of the repeats, beside the issue's targets; they vary with the machine and
  decide nothing about a regression.

Writes reports/bench.md and reports/bench.json (format `signorini-bench/2`, fields in
docs/src/outputs.md). Exits 1 when a figure is a regression or a check costs more than its
bound (missed), 0 otherwise (undecided figures are named in the report).
"""

import argparse
import hashlib
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

CHECKS_SWITCH = "SIGNORINI_BENCHMARK_CHECKS"
REGRESSION = 1.10
CHECK_BOUNDS = {"1d": 1.05, "3d": 1.03}
NS_1D_TARGET = 10.0
NS_3D_TARGET = 100.0

SCHEMES = [
    "crank-nicolson",
    "newmark-1",
    "newmark-2",
    "backward-euler",
    "paoli-schatzman-e0",
    "paoli-schatzman-e0.5",
    "paoli-schatzman-e1",
]
MASSES = ["standard", "redistributed"]


def run_1d(scheme, mass):
    """The step kernel: one run of the Dirichlet bar at NX = 640 with the scene's observables."""
    return ["run", "scenes/bar1d-dirichlet.json", "--scheme", scheme, "--mass", mass, "--nx", "640"]


def run_3d(level):
    """The 3D bar, Crank–Nicolson, redistributed mass, T = 2, the default step solver."""
    return ["run", "scenes/bar3d.json", "--scheme", "crank-nicolson", "--mass", "redistributed",
            "--nx", str(level)]


class Measure:
    """One process: CPU seconds (user + system), wall seconds, peak resident MB, dof-steps."""

    def __init__(self, cpu, wall, peak_mb, dof_steps):
        self.cpu, self.wall, self.peak_mb, self.dof_steps = cpu, wall, peak_mb, dof_steps


def measure(binary, args, env_extra, cwd):
    """Runs `binary args` in `cwd` with `env_extra` added to the environment; None on failure."""
    env = dict(os.environ, CI="true", **env_extra)
    with tempfile.TemporaryDirectory() as scratch, tempfile.TemporaryFile() as out:
        args = [a.replace("{scratch}", scratch) for a in args]
        start = time.perf_counter()
        proc = subprocess.Popen([binary] + args, cwd=cwd, env=env, stdout=out,
                                stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            return None
        out.seek(0)
        text = out.read().decode("utf-8", "replace")
    dof_steps = None
    found = re.search(r"(\d+) steps, (\d+) dofs", text) or re.search(r"(\d+) dofs,.* (\d+) steps", text)
    if found:
        dof_steps = int(found.group(1)) * int(found.group(2))
    return Measure(usage.ru_utime + usage.ru_stime, wall, usage.ru_maxrss / 1024.0, dof_steps)


def alternate(a, b, args, repeats, cwd, label):
    """`repeats` runs of `args` by each side `a`, `b` = (binary, env), in ABBA order: the lists of
    their measures (None when a run failed)."""
    first, second = [], []
    for r in range(repeats):
        order = [(a, first), (b, second)] if r % 2 == 0 else [(b, second), (a, first)]
        for (binary, env), into in order:
            m = measure(binary, args, env, cwd)
            if m is None:
                print(f"  {label}: `{' '.join(args)}` failed with {binary}", file=sys.stderr)
                return None, None
            into.append(m)
    return first, second


def interval(values):
    """The median of `values` and their range."""
    return {"median": statistics.median(values), "low": min(values), "high": max(values)}


def decide(ratio, bound, pairs):
    """`ok` when the whole interval is at or below `bound`, `over` when above it, else undecided
    (always for one pair, whose range is no interval)."""
    if pairs < 2:
        return "undecided"
    if ratio["high"] <= bound:
        return "ok"
    if ratio["low"] > bound:
        return "over"
    return "undecided"


def compared(label, args, a, b, repeats, cwd, bound, what):
    """One figure measured side by side: `b`'s CPU time over `a`'s, pair by pair."""
    t0 = time.perf_counter()
    first, second = alternate(a, b, args, repeats, cwd, label)
    if first is None:
        print(f"{label}: not measured", file=sys.stderr)
        return {"what": label, "command": " ".join(args), "measured": False}
    ratios = [s.cpu / f.cpu for f, s in zip(first, second)]
    ratio = interval(ratios)
    verdict = decide(ratio, bound, repeats)
    figure = {
        "what": label,
        "command": " ".join(args),
        "measured": True,
        "pairs": repeats,
        "ratio": ratio,
        "bound": bound,
        "verdict": verdict,
        what[0] + "_cpu_seconds": interval([f.cpu for f in first]),
        what[1] + "_cpu_seconds": interval([s.cpu for s in second]),
        "cpu_seconds": interval([s.cpu for s in second]),
        "wall_seconds": interval([s.wall for s in second]),
        "peak_mb": max(s.peak_mb for s in second),
    }
    if second[0].dof_steps:
        figure["dof_steps"] = second[0].dof_steps
        figure["ns_per_dof_step"] = interval([s.cpu * 1e9 / s.dof_steps for s in second])
    print(f"{label}: ratio {ratio['median']:.3f} [{ratio['low']:.3f}, {ratio['high']:.3f}] "
          f"{verdict} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return figure


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--current", required=True)
    parser.add_argument("--baseline", required=True)
    parser.add_argument("--baseline-commit", required=True)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--fine", action="store_true")
    parser.add_argument("--only", choices=["checks", "baseline"])
    parser.add_argument("--out", default="reports")
    options = parser.parse_args()
    cwd = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    current = (os.path.abspath(options.current), {})
    unchecked = (current[0], {CHECKS_SWITCH: "off"})
    baseline = (os.path.abspath(options.baseline), {})
    n = options.repeats
    started = time.perf_counter()

    checks = []
    if options.only != "baseline":
        for dim, label, args in [
            ("1d", "1D run, crank-nicolson / redistributed, NX = 640", run_1d("crank-nicolson", "redistributed")),
            ("3d", "3D level 80 run (CN, redistributed, T = 2)", run_3d(80)),
        ]:
            figure = compared(label, args, unchecked, current, max(n, 7), cwd,
                              CHECK_BOUNDS[dim], ("unchecked", "checked"))
            checks.append(figure)

    kernels, runs = [], []
    if options.only != "checks":
        for scheme in SCHEMES:
            for mass in MASSES:
                kernels.append(compared(f"kernel {scheme} / {mass}, NX = 640", run_1d(scheme, mass),
                                        baseline, current, n, cwd, REGRESSION, ("baseline", "current")))
        runs.append(compared("Tables 1–2 study (`study scenes/bar1d-dirichlet.json`)",
                             ["study", "scenes/bar1d-dirichlet.json"], baseline, current,
                             max(3, n // 2), cwd, REGRESSION, ("baseline", "current")))
        if options.fine:
            runs.append(compared("1D round-off sensitivity, 4 members (`sensitivity … --members 4`)",
                                 ["sensitivity", "scenes/bar1d-dirichlet.json", "--members", "4",
                                  "--out", "{scratch}"],
                                 baseline, current, 3, cwd, REGRESSION, ("baseline", "current")))
        levels = [80, 160] + ([320] if options.fine else [])
        for level in levels:
            runs.append(compared(f"3D level {level} run (CN, redistributed, T = 2)", run_3d(level),
                                 baseline, current, n if level == 80 else 3 if level == 160 else 1,
                                 cwd, REGRESSION, ("baseline", "current")))

    report = {
        "format": "signorini-bench/2",
        "baseline_commit": options.baseline_commit,
        "regression_bound": REGRESSION,
        "checks": checks,
        "kernels": kernels,
        "runs": runs,
        "seconds": time.perf_counter() - started,
    }
    failed = [f for f in checks + kernels + runs if f.get("verdict") == "over" or not f["measured"]]
    report["passed"] = not failed
    markdown = render(report)
    print(markdown)
    out = os.path.join(cwd, options.out)
    os.makedirs(out, exist_ok=True)
    write_recorded(out, {
        "bench.md": markdown.encode("utf-8"),
        "bench.json": (json.dumps(report, indent=2, ensure_ascii=False) + "\n").encode("utf-8"),
    })
    return 0 if report["passed"] else 1


def write_recorded(out, files):
    """Writes `files` (name → bytes) into `out`, each through a temporary file and a rename, and
    records their SHA-256 in the directory's manifest (.signorini-manifest.json, the harness's
    record of the files it wrote, src/harness/files/manifest.rs) when there is one, so that the
    harness's commands keep treating them as its own."""
    for name, data in files.items():
        path = os.path.join(out, name)
        with open(path + ".tmp", "wb") as f:
            f.write(data)
        os.replace(path + ".tmp", path)
    manifest = os.path.join(out, ".signorini-manifest.json")
    if not os.path.exists(manifest):
        return
    with open(manifest, encoding="utf-8") as f:
        recorded = json.load(f)
    for name, data in files.items():
        recorded["files"][name] = hashlib.sha256(data).hexdigest()
    recorded["files"] = dict(sorted(recorded["files"].items()))
    with open(manifest + ".tmp", "w", encoding="utf-8") as f:
        f.write(json.dumps(recorded, indent=2, ensure_ascii=False))
    os.replace(manifest + ".tmp", manifest)


def ratio_text(figure):
    r = figure["ratio"]
    return f"{r['median']:.3f} [{r['low']:.3f}, {r['high']:.3f}]"


def word(figure, over):
    return {"ok": "ok", "over": over, "undecided": "undecided"}[figure["verdict"]]


def spread(i, fmt):
    return f"{fmt.format(i['median'])} [{fmt.format(i['low'])}, {fmt.format(i['high'])}]"


def render(report):
    md = ["# Speed side by side (`make bench`)", ""]
    md.append(f"Baseline: commit `{report['baseline_commit']}`, built beside the working tree and "
              "run in alternation with it in one go (scripts/bench.py). Every figure is a ratio "
              "of CPU times (user + system) with the range of its pairs, a distribution-free "
              "interval for the median ratio; a ratio whose whole interval lies above "
              f"{report['regression_bound']:.2f} is a regression, one whose interval straddles it "
              f"is undecided. This run took {report['seconds']:.0f} s.")
    md.append("")
    if report["checks"]:
        md += ["## What the per-step checks cost", "",
               "The working tree's binary with its checks (non-finite values, energy balance, "
               "physics monitor) on, over the same binary with them off, in alternation.", "",
               "| run | pairs | ratio on / off [range] | bound | | CPU s with checks [range] |",
               "|---|---|---|---|---|---|"]
        for f in report["checks"]:
            if not f["measured"]:
                md.append(f"| {f['what']} | | not measured | | MISSED | |")
                continue
            md.append(f"| {f['what']} | {f['pairs']} | {ratio_text(f)} | ≤ {f['bound']:.2f} | "
                      f"{word(f, 'MISSED')} | {spread(f['cpu_seconds'], '{:.3f}')} |")
        md.append("")
    if report["kernels"]:
        md += ["## Step kernels against the baseline", "",
               "`signorini run scenes/bar1d-dirichlet.json --nx 640` (Δx/Δt = 10, T = 3, 19 200 "
               "steps, the scene's seven norms and histories), each scheme × mass. The CPU time "
               "per dof-step is the working tree's, for information (the issue's target is "
               f"≤ {NS_1D_TARGET:.0f} ns).", "",
               "| scheme / mass | pairs | ratio to baseline [range] | | ns per dof-step [range] |",
               "|---|---|---|---|---|"]
        for f in report["kernels"]:
            if not f["measured"]:
                md.append(f"| {f['what']} | | not measured | MISSED | |")
                continue
            ns = spread(f["ns_per_dof_step"], "{:.1f}") if "ns_per_dof_step" in f else ""
            md.append(f"| {f['what']} | {f['pairs']} | {ratio_text(f)} | "
                      f"{word(f, 'REGRESSION')} | {ns} |")
        md.append("")
    if report["runs"]:
        md += ["## Studies and 3D runs against the baseline", "",
               "| what | pairs | ratio to baseline [range] | | CPU s [range] | wall s [range] | peak MB |",
               "|---|---|---|---|---|---|---|"]
        for f in report["runs"]:
            if not f["measured"]:
                md.append(f"| {f['what']} | | not measured | MISSED | | | |")
                continue
            md.append(f"| {f['what']} | {f['pairs']} | {ratio_text(f)} | {word(f, 'REGRESSION')} | "
                      f"{spread(f['cpu_seconds'], '{:.2f}')} | {spread(f['wall_seconds'], '{:.2f}')} | "
                      f"{f['peak_mb']:.0f} |")
        for f in report["runs"]:
            if f["measured"] and "ns_per_dof_step" in f and f["what"].startswith("3D level 80"):
                md += ["", f"3D level 80: {spread(f['ns_per_dof_step'], '{:.0f}')} ns of CPU time "
                       f"per dof-step for the whole run (setup included; the issue's target is "
                       f"≤ {NS_3D_TARGET:.0f} for the stepping)."]
        md.append("")
    md.append("No regression and every check within its bound." if report["passed"] else
              "At least one regression, missed bound or unmeasured figure (`make bench` exits 1).")
    md.append("")
    return "\n".join(md)


if __name__ == "__main__":
    sys.exit(main())
