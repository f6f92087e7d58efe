#!/usr/bin/env python3
"""Regenerates docs/performance.md, the sweep's plot and CSV in docs/, and the headline table of
README.md from ivgi's own benchmarks, so that no figure is copied by hand.

Usage: tools/perf_tables.py [--ivgi build/ivgi] [--runs 3] [--threads 2]
                            [--only passes|programs|scaling|sweep|accuracy|real|ar|flicker|equal|size|glossy]

--only regenerates one section alone: `passes` (per pass, and the README's rows of the frame time),
`programs` (per program, with bench --per-program), `scaling` (cost against tessellation), `sweep`
(the speed/accuracy sweep, its plot and CSV; about a quarter of an hour), `accuracy` (where iv's
error lies, its ratio images, and the README's row of iv's error), `real` (the real files), `ar`
(ar per --dirs, and the README's rows of ar), `flicker` (the sequences' temporal error), `equal`
(iv and ar against pt at equal error, and the README's rows of it), `size` (iv, ar and pt
against the scene's size at equal error, the Blender room among them; about 45 minutes) or
`glossy` (the glossy Cornell box against pt; about five minutes). The section then names the
machine and date it was measured on, since the rest of the document may come from another run.

The default binary, build/ivgi, is built first, so that the figures are the sources' (a binary
left from an experiment would write its own into the tables). Every timing is the median over
--runs runs of `ivgi bench` (each itself a median over frames), with LP_NUM_THREADS set to
--threads for lavapipe and pt on as many threads. The equal-error runs
need a converged pt reference of the animated Cornell box's frame 0 at 320×240 (4096 spp, a few
minutes), the flicker table a pt sequence and the real-file table pt references of its scenes: all
are rendered into the scratch folder. The Blender room is made with Debian's blender where it is
installed (tools/scenes/blender_room.py), else left out.
"""
import argparse
import csv
import datetime
import json
import os
import pathlib
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


class Runner:
    def __init__(self, ivgi, threads, scratch):
        self.ivgi = str(ivgi)
        self.env = dict(os.environ, LP_NUM_THREADS=str(threads))
        self.threads = threads
        self.scratch = pathlib.Path(scratch)
        self.count = 0

    def run(self, *args, timeout=None):
        """ivgi's output; subprocess.TimeoutExpired past `timeout` seconds."""
        command = [self.ivgi, *map(str, args)]
        print("  $", " ".join(command), file=sys.stderr, flush=True)
        done = subprocess.run(command, env=self.env, capture_output=True, text=True, timeout=timeout)
        if done.returncode != 0:
            sys.exit(f"perf_tables: {' '.join(command)} failed:\n{done.stderr}")
        return done.stdout

    def json(self, *args, timeout=None):
        self.count += 1
        path = self.scratch / f"result_{self.count}.json"
        self.run(*args, "--json", path, timeout=timeout)
        return json.loads(path.read_text())


def median(values):
    return statistics.median(values)


def bench(r, runs, cells, frames, warmup, extra=()):
    """Per pass, the median over runs of each run's median GPU ms; the last run's JSON."""
    results = [r.json("bench", "cornell", "--cells", cells, "--size", "320x240", "--frames", frames,
                      "--warmup", warmup, *extra) for _ in range(runs)]
    passes = {p: median([j["passes"][p]["medianMs"] for j in results]) for p in results[0]["passes"]}
    return passes, results[-1]


def fmt(ms):
    return f"{ms:,.1f}" if ms >= 10 else f"{ms:.2f}"


def per_pass_table(r, runs):
    order = ["animate", "surfels", "direct light", "raster", "shown", "refit", "links", "prune", "receivers", "interpolation",
             "bounces", "direct pixels", "resolve", "total"]
    columns, results = {}, {}
    for cells in (8, 26):
        columns[cells], results[cells] = bench(r, runs, cells, 20, 3)
    head = " | ".join(f"`--cells {c}` ({results[c]['counts']['surfels']:,} surfels, "
                      f"{results[c]['solver']['receivers']:,} receivers)" for c in columns)
    lines = [f"| pass | {head} |", "|---|---|---|"]
    for p in order:
        if p in columns[8]:  # with every surfel a receiver (a GPU's default) there is no receivers pass
            lines.append(f"| {p} | {fmt(columns[8][p])} | {fmt(columns[26][p])} |")
    fps = {c: 1000.0 / columns[c]["total"] for c in columns}
    lines.append(f"| frames per second | {fps[8]:.1f} | {fps[26]:.1f} |")
    return "\n".join(lines), results[26]["device"], columns


PROGRAMS_INTRO = """`ivgi bench cornell --cells 26 --size 320x240 --method M --per-program` at the defaults (iv: 20
frames after 3 warm-up frames, ar: 3 after 1): every dispatch timed on its own, by its program (one
compute shader each). The programs' times add up to less than the frame: the barriers, fills and
copies between dispatches belong to the frame's passes, not to a program. The timestamps
themselves slow the frame: the last row of each table is the same frame timed without them."""


def programs_table(r, runs):
    """The animated Cornell box at --cells 26, each dispatch timed by its program (bench --per-program):
    iv's and ar's, the slowest first, medians over `runs` runs of each run's median; and the frame
    without the dispatches' timestamps, from as many runs alternated with them."""
    tables = []
    for method, frames, warmup in (("iv", 20, 3), ("ar", 3, 1)):
        results, plain = [], []
        for _ in range(runs):
            args = ("bench", "cornell", "--cells", 26, "--size", "320x240", "--frames", frames, "--warmup", warmup,
                    "--method", method)
            results.append(r.json(*args, "--per-program"))
            plain.append(r.json(*args)["passes"]["total"]["medianMs"])
        times = {n: median([j["programs"][n]["medianMs"] for j in results if n in j["programs"]])
                 for n in results[0]["programs"]}
        names = sorted(times, key=lambda n: -times[n])
        total = median([j["passes"]["total"]["medianMs"] for j in results])
        lines = [f"| {method}: program | ms a frame | share of the frame | dispatches a frame |", "|---|---|---|---|"]
        for name in names:
            ms = times[name]
            dispatches = results[0]["programs"][name]["dispatches"]
            lines.append(f"| `{name}` | {fmt(ms)} | {100.0 * ms / total:.1f} % | {dispatches:.0f} |")
        count = sum(results[0]["programs"][n]["dispatches"] for n in names)
        lines.append(f"| the frame (its passes) | {fmt(total)} | 100 % | {count:.0f} |")
        lines.append(f"| the frame without `--per-program` | {fmt(median(plain))} | | |")
        tables.append("\n".join(lines))
    return "\n\n".join(tables)


def scaling_table(r, runs, every_most=52):
    """The animated Cornell box at more cells a side: adaptive receivers (--receiver-tol 0.4, a CPU
    device's default) against every surfel a receiver (--receiver-tol 0, a GPU's; up to `every_most`
    cells: beyond 52, a frame takes many seconds on lavapipe)."""
    lines = ["| `--cells` | surfels | receivers | links | device MiB | host peak MiB | frame ms | fps | every surfel: frame ms |",
             "|---|---|---|---|---|---|---|---|---|"]
    for cells, frames in ((8, 10), (26, 10), (52, 5), (100, 3)):
        passes, j = bench(r, runs, cells, frames, 2, ("--receiver-tol", 0.4))
        c, s = j["counts"], j["solver"]
        total = passes["total"]
        every = "—"
        if cells <= every_most:
            full, _ = bench(r, runs, cells, frames, 2, ("--receiver-tol", 0))
            every = fmt(full["total"])
        lines.append(f"| {cells} | {c['surfels']:,} | {s['receivers']:,} | {s['links']:,} | "
                     f"{j['bytesAllocated'] / 2**20:.1f} | {j['hostPeakMiB']:,.0f} | {fmt(total)} | {1000.0 / total:.1f} | "
                     f"{every} |")
    return "\n".join(lines)


def cells26_reference(r):
    """Frame 0 of the animated Cornell box at --cells 26 and 320×240, pt at 4096 spp: rendered once."""
    reference = r.scratch / "pt_cells26_0000.exr"
    if not reference.exists():
        r.run("render", "cornell", "--cells", 26, "--method", "pt", "--spp", 4096, "--size", "320x240", "--frames", 0,
              "--format", "exr", "--threads", r.threads, "--out", r.scratch / "pt_cells26_%04d")
    return reference


def sweep_table(r):
    """The sweep at 4×4 samples a pixel: a pt pixel averages its paths over the pixel, so that at one
    sample a pixel the edges' aliasing, which no setting changes, would flatten the front."""
    out = r.scratch / "sweep"
    r.run("sweep", "cornell", "--cells", 26, "--reference", cells26_reference(r), "--supersample", 4, "--method",
          "iv,ar", "--bins", "8,16,24,32", "--receiver-tol", "0,0.1,0.2,0.4,0.8", "--dirs", "2,4,6,8", "--repeats", 3,
          "--out", out)
    shutil.copy(out / "sweep.csv", DOCS / "sweep_cornell.csv")
    shutil.copy(out / "sweep.png", DOCS / "sweep_cornell.png")
    return sweep_markdown(out / "sweep.csv")


def sweep_markdown(csv_path):
    """A sweep's rows as two tables: iv's settings, then ar's."""
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    lines = ["| bins | `--receiver-tol` | receivers | GPU ms | MiB | relMSE | FLIP | on the front |",
             "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        if row["method"] != "iv":
            continue
        tol = "0 (every surfel)" if float(row["receiverTol"]) == 0 else row["receiverTol"]
        lines.append(f"| 6×{row['bins']}×{row['bins']} | {tol} | {int(row['receivers']):,} | {fmt(float(row['ms']))} | "
                     f"{int(row['bytes']) / 2**20:.1f} | {float(row['relMSE']):.4f} | {float(row['FLIP']):.3f} | "
                     f"{'yes' if row['pareto'] == '1' else ''} |")
    lines += ["", "| ar, `--dirs` | iterations | GPU ms | MiB | relMSE | FLIP | on the front |",
              "|---|---|---|---|---|---|---|"]
    for row in rows:
        if row["method"] == "ar":
            lines.append(f"| 6×{row['dirs']}×{row['dirs']} | {row['iterationsRun']} | {fmt(float(row['ms']))} | "
                         f"{int(row['bytes']) / 2**20:.1f} | {float(row['relMSE']):.4f} | {float(row['FLIP']):.3f} | "
                         f"{'yes' if row['pareto'] == '1' else ''} |")
    return "\n".join(lines)


def ar_table(r):
    """ar on the animated Cornell box at --cells 26 and 320×240 (issue 22's target case), per --dirs: a
    restart (every frame from the emission, `--restart-every 1`: the median GPU ms over 3 frames after
    a warm-up frame), the defaults' chains over the whole animation (48 frames after a warm-up frame:
    median and mean), and frame 0's relMSE against a 4096-spp pt reference of that scene (frame 0
    starts a chain, so it is the restart's image)."""
    reference = cells26_reference(r)
    lines = ["| `--dirs` | links | tables MiB | iterations, a restart / chained (range) | restart ms | chained ms, "
             "median / mean | fps over the animation | relMSE |",
             "|---|---|---|---|---|---|---|---|"]
    figures = {}
    for dirs in (2, 4, 6, 8):
        cold = r.json("bench", "cornell", "--cells", 26, "--size", "320x240", "--frames", 3, "--warmup", 1, "--method",
                      "ar", "--dirs", dirs, "--restart-every", 1)
        chained = r.json("bench", "cornell", "--cells", 26, "--size", "320x240", "--frames", 48, "--warmup", 1,
                         "--method", "ar", "--dirs", dirs)
        out = r.scratch / f"ar_cells26_d{dirs}"
        r.run("render", "cornell", "--cells", 26, "--method", "ar", "--dirs", dirs, "--size", "320x240", "--frames", 0,
              "--format", "exr", "--out", out / "f_%04d")
        rel = r.json("compare", out / "f_0000.exr", reference)["frames"][0]["metrics"]["relMSE"]
        restart, s = cold["passes"]["total"]["medianMs"], chained["solver"]
        median_ms, mean_ms = chained["passes"]["total"]["medianMs"], chained["passes"]["total"]["meanMs"]
        iterations = sorted(f["solver"]["iterations"] for f in chained["frames"])
        figures[dirs] = (mean_ms, rel, restart)
        lines.append(f"| {dirs} | {s['links']:,} | {s['tableBytes'] / 2**20:.1f} | {cold['solver']['iterations']} / "
                     f"{median(iterations):.0f} ({iterations[0]:.0f}–{iterations[-1]:.0f}) | {fmt(restart)} | "
                     f"{fmt(median_ms)} / {fmt(mean_ms)} | {1000.0 / mean_ms:.2f} | {rel:.4f} |")
    return "\n".join(lines), figures


def ar_rows(figures):
    """The README headline's rows of ar on the animated Cornell box (ar_table's figures)."""
    return [f"| ar (antiradiance) at `--cells 26`, 320×240, defaults (`--dirs 4`) / `--dirs 8`, over the animation | "
            f"{figures[4][0]:,.0f} ms a frame ({1000.0 / figures[4][0]:.1f} fps), relMSE {figures[4][1]:.4f} / "
            f"{figures[8][0]:,.0f} ms, relMSE {figures[8][1]:.4f} |",
            f"| ar at `--dirs 2`, the same | {figures[2][0]:,.0f} ms a frame ({1000.0 / figures[2][0]:.1f} fps), "
            f"relMSE {figures[2][1]:.4f} |"]


def accuracy_table(r):
    """Where iv's error lies: frame 0 of the animated Cornell box at --cells 26 and 320×240 against the
    4096-spp pt reference, at one sample a pixel and at 4×4 (as relMSE, and as ratio images written to
    docs/); and the closed furnace at defaults, whose exact radiance is 1/(1−ρ). Returns the table
    and the relMSE of each setting and sample count."""
    reference = cells26_reference(r)
    lines = ["| iv | relMSE, 1 sample a pixel | relMSE, 4×4 | FLIP, 4×4 | test / pt per pixel, 4×4 |",
             "|---|---|---|---|---|"]
    errors = {}
    for name, slug, extra in (("defaults", "defaults", ()), ("every surfel a receiver", "every_surfel",
                                                             ("--receiver-tol", 0))):
        metrics = {}
        for samples in (1, 4):
            out = r.scratch / f"iv_cells26_{slug}_{samples}"
            r.run("render", "cornell", "--cells", 26, "--size", "320x240", "--supersample", samples, "--frames", 0,
                  "--format", "exr", "--out", out / "f_%04d", *extra)
            png = f"ratio_cornell_{slug}.png"
            ratio = ("--ratio", DOCS / png) if samples == 4 else ()
            metrics[samples] = r.json("compare", out / "f_0000.exr", reference, *ratio)["frames"][0]["metrics"]
            errors[(slug, samples)] = metrics[samples]["relMSE"]
        lines.append(f"| {name} | {metrics[1]['relMSE']:.4f} | {metrics[4]['relMSE']:.4f} | {metrics[4]['FLIP']:.3f} | "
                     f"![{name}]({png}) |")
    lines += ["", "| furnace, defaults | mean radiance | exact | error |", "|---|---|---|---|"]
    for albedo in (0.5, 0.9):
        scene = r.scratch / f"furnace_{albedo}.gltf"
        r.run("scene", "furnace", "--cells", 12, "--albedo", albedo, "--emission", 1, "--out", scene)
        out = r.scratch / f"furnace_{albedo}"
        r.run("render", scene, "--size", "160x120", "--frames", 0, "--format", "exr", "--out", out / "f_%04d")
        stats = subprocess.run(["oiiotool", str(out / "f_0000.exr"), "--ch", "R", "--printstats"], capture_output=True,
                               text=True, check=True).stdout
        mean = float(re.search(r"Stats Avg:\s*([-0-9.eE+]+)", stats).group(1))
        exact = 1.0 / (1.0 - albedo)
        lines.append(f"| ρ {albedo}, 12 cells a face | {mean:.4f} | {exact:.4f} | {100.0 * (mean / exact - 1.0):+.2f} % |")
    return "\n".join(lines), errors


def glossy_table(r, runs):
    """The glossy Cornell box (`--glossy`: a polished floor, a metal tall block, a satin short block)
    at --cells 26, 320×240, frame 0 against pt at 4096 spp: iv and ar at one sample a pixel and at
    4×4, with the region furthest off (tools/cornell_regions.py) and the metal block's front; and
    the animated frame's median GPU time against the same box's diffuse frame."""
    reference = r.scratch / "pt_glossy_0000.exr"
    r.run("render", "cornell", "--glossy", "--cells", 26, "--method", "pt", "--spp", 4096, "--size", "320x240",
          "--frames", 0, "--format", "exr", "--threads", r.threads, "--out", r.scratch / "pt_glossy_%04d")
    lines = ["| method | relMSE, 1 sample a pixel | relMSE, 4×4 | FLIP, 4×4 | region furthest off, 4×4 | "
             "tall (metal) block's front, 4×4 | ms a frame: glossy / diffuse |",
             "|---|---|---|---|---|---|---|"]
    for method in ("iv", "ar"):
        metrics, regions = {}, {}
        for samples in (1, 4):
            out = r.scratch / f"glossy_{method}_{samples}"
            r.run("render", "cornell", "--glossy", "--cells", 26, "--method", method, "--size", "320x240",
                  "--supersample", samples, "--frames", 0, "--format", "exr", "--out", out / "f_%04d")
            metrics[samples] = r.json("compare", out / "f_0000.exr", reference)["frames"][0]["metrics"]
            figures = out / "regions.json"
            subprocess.run(["/usr/bin/python3", str(ROOT / "tools/cornell_regions.py"), str(out / "f_0000.exr"),
                            str(reference), "--json", str(figures)], check=True, capture_output=True)
            regions[samples] = json.loads(figures.read_text())["regions"]
        worst = max(regions[4].items(), key=lambda item: abs(item[1]["ratio"] - 1.0))
        # The two variants' runs alternated, so that the machine's drift over them falls on both alike.
        times = {("--glossy",): [], (): []}
        for _ in range(runs):
            for variant, runs_ms in times.items():
                runs_ms.append(r.json("bench", "cornell", *variant, "--cells", 26, "--size", "320x240", "--method",
                                      method, "--frames", 10, "--warmup", 3)["passes"]["total"]["medianMs"])
        ms = {variant: median(runs_ms) for variant, runs_ms in times.items()}
        lines.append(f"| {method} | {metrics[1]['relMSE']:.4f} | {metrics[4]['relMSE']:.4f} | "
                     f"{metrics[4]['FLIP']:.3f} | {worst[0]}: {worst[1]['ratio']:.3f} | "
                     f"{regions[4]['tall block, front']['ratio']:.3f} | "
                     f"{fmt(ms[('--glossy',)])} / {fmt(ms[()])} ({ms[('--glossy',)] / ms[()]:.2f}×) |")
    return "\n".join(lines)


def at_equal(results, suffix, ms_key):
    """pt's time at the solver's error and the speed-up (medians of bench --equal-error `results`),
    or the bound where pt never got there."""
    reached = [j for j in results if j.get("ratio" + suffix)]
    if reached:
        return (f"{median([j[ms_key] for j in reached]):,.0f}",
                median([j["ratio" + suffix] for j in reached]), "")
    bound = median([j["ratio" + suffix + "LowerBound"] for j in results])
    return "not within the ladder", bound, "> "


def equal_error_table(r, runs):
    reference = r.scratch / "pt_reference_0000.exr"
    r.run("render", "--method", "pt", "--spp", 4096, "--size", "320x240", "--frames", 0, "--format", "exr",
          "--threads", r.threads, "--out", r.scratch / "pt_reference_%04d", "--json", r.scratch / "pt_reference.json")
    reference_s = json.loads((r.scratch / "pt_reference.json").read_text())["frames"][0]["totalCpuMs"] / 1000
    lines = ["| setting | ms per frame | relMSE | pt ms at that relMSE | faster than pt by | FLIP | pt ms at that FLIP "
             "| faster than pt by |", "|---|---|---|---|---|---|---|---|"]
    ratios = {}

    for name, extra in (("defaults", ()), ("every surfel a receiver", ("--receiver-tol", 0)),
                        ("ar, defaults", ("--method", "ar"))):
        results = [r.json("bench", "--equal-error", "--size", "320x240", "--reference", reference, "--threads",
                          r.threads, *extra) for _ in range(runs)]
        iv_ms = median([j["solver"]["meanGpuMs"] for j in results])
        rel = median([j["solver"]["relMSE"] for j in results])
        flip = median([j["solver"]["FLIP"] for j in results])
        pt_ms, ratio, more = at_equal(results, "", "ptMsAtEqualError")
        pt_flip_ms, ratio_flip, more_flip = at_equal(results, "Flip", "ptMsAtEqualFlip")
        ratios[name] = (ratio, ratio_flip)
        lines.append(f"| {name} | {fmt(iv_ms)} | {rel:.5f} | {pt_ms} | {more}{ratio:.1f}× | {flip:.4f} | {pt_flip_ms} "
                     f"| {more_flip}{ratio_flip:.1f}× |")
    return "\n".join(lines), reference_s, ratios, reference


SIZE_INTRO = """Each method's time against the path tracer's at the same error, as the scene grows: iv and ar
on lavapipe, pt on the same 2 cores (`ivgi bench --equal-error`: pt renders the frame at 1, 2, 4, …
spp until it reaches the solver's relMSE, or FLIP, and its time there is interpolated log–log).
The animated Cornell box at 8 to 100 cells a side (frame 0 at 320×240 against pt at 4096 spp; iv and
ar over 10 animated frames, each solved anew), the Blender room (tools/scenes/blender_room.py:
frame 0 at 480×270 against pt at 1024 spp; 10 frames of Suzanne turning, after 2 not measured)
and 2CylinderEngine (480×270 against pt at 1024 spp; its one frame solved in full, every run of a
frame redone counted). One run each."""
GLOSSY_INTRO = """`ivgi render cornell --glossy --cells 26 --size 320x240 --supersample S --frames 0` (the
polished floor at roughness 0.2, the metal tall block at 0.3, the satin short block at 0.5; the
walls Lambertian) against pt at 4096 spp, with `tools/cornell_regions.py`'s regions; and `ivgi
bench cornell [--glossy] --cells 26 --size 320x240 --frames 10 --warmup 3` for the animated frame's
cost. iv and ar draw the direct light's highlights per pixel and reflect the indirect light through
the lobes from the directions they keep (iv's links, ar's tables: at `--dirs 4` as of roughness
0.43 at least)."""
ENGINE = pathlib.Path("/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb")


SIZE_LIMIT_S = 900  # a method's equal-error run on one scene; past it the row says so


def size_row(name, method, j):
    """One row of size_table from a bench --equal-error result (None: stopped at SIZE_LIMIT_S)."""
    if j is None:
        return f"| {name} | | {method} | stopped after {SIZE_LIMIT_S // 60} min | | | | | | |"
    pt_ms, ratio, more = at_equal([j], "", "ptMsAtEqualError")
    pt_flip_ms, ratio_flip, more_flip = at_equal([j], "Flip", "ptMsAtEqualFlip")
    sv = j["solver"]
    def times(x):  # slower than pt: two digits of the fraction
        return f"{x:.1f}×" if x >= 1 else f"{x:.2g}×"
    return (f"| {name} | {j['surfels']:,} | {method} | {fmt(sv['meanGpuMs'])} | {sv['relMSE']:.5f} | {pt_ms} | "
            f"{more}{times(ratio)} | {sv['FLIP']:.4f} | {pt_flip_ms} | {more_flip}{times(ratio_flip)} |")


def size_table(r):
    """iv, ar and pt against the scene's size, each at the others' error (SIZE_INTRO). One run each:
    the largest take many minutes."""
    scenes = [(f"Cornell box, `--cells {c}`", ("cornell", "--cells", c), "320x240", 4096,
               ("--frames", 10, "--warmup", 2)) for c in (8, 26, 52, 100)]
    room = blender_room(r)
    if room:
        scenes.append(("the Blender room (Suzanne turning)", (room,), "480x270", 1024, ("--frames", 10, "--warmup", 2)))
    if ENGINE.exists():
        scenes.append(("2CylinderEngine.glb", (ENGINE,), "480x270", 1024, ("--frames", 1, "--warmup", 0)))
    lines = ["| scene | surfels | method | ms per frame | relMSE | pt ms at that relMSE | faster than pt by | FLIP "
             "| pt ms at that FLIP | faster than pt by |", "|---|---|---|---|---|---|---|---|---|---|"]
    for k, (name, source, size, spp, frames) in enumerate(scenes):
        print(f"size: {name}", file=sys.stderr)
        r.run("render", *source, "--method", "pt", "--spp", spp, "--size", size, "--frames", 0, "--format", "exr",
              "--threads", r.threads, "--out", r.scratch / f"size{k}_%04d")
        for method in ("iv", "ar"):
            try:
                j = r.json("bench", *source, "--method", method, "--equal-error", "--size", size, "--reference",
                           r.scratch / f"size{k}_0000.exr", "--threads", r.threads, *frames, timeout=SIZE_LIMIT_S)
            except subprocess.TimeoutExpired:
                j = None
            lines.append(size_row(name, method, j))
    return "\n".join(lines)


def flicker_table(r):
    """The animated Cornell box's first 12 frames at 160×120: each iv setting against a pt sequence, per
    frame and as the frame-to-frame change (ivgi compare's temporal relMSE)."""
    scene = ["cornell", "--cells", "26", "--frames", "0-11", "--size", "160x120", "--format", "exr"]
    pt = r.scratch / "flicker_pt"
    r.run("render", *scene, "--method", "pt", "--spp", 1024, "--threads", r.threads, "--out", pt / "f_%04d")
    lines = ["| setting | mean relMSE of the frames | temporal relMSE |", "|---|---|---|"]
    for name, extra in (("iv, defaults (adaptive receivers)", ()), ("iv, every surfel a receiver", ("--receiver-tol", 0)),
                        ("ar, defaults (chains of 16 frames)", ("--method", "ar")),
                        ("ar, every frame from the emission", ("--method", "ar", "--restart-every", 1))):
        out = r.scratch / f"flicker_{len(lines)}"
        r.run("render", *scene, *extra, "--out", out / "f_%04d")
        j = r.json("compare", out, pt)
        frames = median([f["metrics"]["relMSE"] for f in j["frames"]])
        lines.append(f"| {name} | {frames:.5f} | {j['summary']['temporal']['relMSE']:.2e} |")
    return "\n".join(lines)


def real_files_table(r, runs):
    """Files nobody here wrote, one frame at 480×270 at defaults: the median wall clock of `runs` renders
    (start-up included) and the error against pt at 1024 spp with the same light."""
    scenes = [("2CylinderEngine.glb (assimp-testmodels)", ENGINE)]
    room = blender_room(r)
    if room:
        scenes.append((ROOM_NAME, room))
    lines = ["| scene | surfels | receivers | wall clock s | device MiB | host peak MiB | relMSE against pt |",
             "|---|---|---|---|---|---|---|"]
    if not any(name.startswith("a room") for name, _ in scenes):
        lines += earlier_room_row()
    for name, path in scenes:
        if not path.exists():
            continue
        base = r.scratch / path.stem

        def timed_render():
            begin = time.monotonic()
            r.run("render", path, "--frames", 0, "--size", "480x270", "--format", "exr", "--out", base / "iv_%04d")
            return time.monotonic() - begin

        seconds = median([timed_render() for _ in range(runs)])
        sidecar = json.loads((base / "iv.json").read_text())
        r.run("render", path, "--method", "pt", "--spp", 1024, "--frames", 0, "--size", "480x270", "--format", "exr",
              "--threads", r.threads, "--out", base / "pt_%04d")
        error = r.json("compare", base / "iv_0000.exr", base / "pt_0000.exr")["frames"][0]["metrics"]["relMSE"]
        lines.append(f"| {name} | {sidecar['counts']['surfels']:,} | {int(sidecar['solver']['receivers']):,} | "
                     f"{seconds:.1f} | {sidecar['bytesAllocated'] / 2**20:,.0f} | "
                     f"{sidecar['frames'][0]['hostPeakMiB']:,.0f} | {error:.4f} |")
    return "\n".join(lines)


ROOM_NAME = "a room written by Blender 3.4's glTF exporter (tools/scenes/blender_room.py)"


def blender_room(r):
    """The room exported by Debian's blender into the scratch folder (once), or None without it."""
    room = r.scratch / "room.glb"
    if room.exists():
        return room
    blender = shutil.which("blender")
    if not blender:
        print("perf_tables: no blender on PATH, the Blender room is left out", file=sys.stderr)
        return None
    # Blender's Python takes its modules from the python3 first on PATH: a pyenv or conda one lacks
    # the numpy its glTF exporter needs, so it runs with the system's PATH.
    export = subprocess.run([blender, "--background", "--factory-startup", "--python-exit-code", "1", "--python",
                             ROOT / "tools/scenes/blender_room.py", "--", room],
                            capture_output=True, text=True, env={**os.environ, "PATH": "/usr/bin:/bin"})
    if export.returncode != 0 or not room.exists():
        print(f"perf_tables: Blender's export failed, the room is left out:\n{export.stderr[-2000:]}", file=sys.stderr)
        return None
    return room


def earlier_room_row():
    """The Blender room's row as docs/performance.md has it, for a run that cannot export the room:
    kept with the date it was measured on, its columns matched to this table's by their headings
    (those it lacks: —)."""
    doc = (DOCS / "performance.md").read_text()
    start = doc.index("| scene | surfels | receivers |")
    section = doc[start:doc.index("\n## ", start)]
    table = [line for line in section.splitlines() if line.startswith("|")]
    heads = [h.strip() for h in table[0].strip("|").split("|")]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in table[2:]]
    room = next((row for row in rows if row[0].startswith("a room")), None)
    if room is None:
        return []
    dated = re.search(r"measured on (\d{4}-\d{2}-\d{2})", room[0]) or re.search(r"on (\d{4}-\d{2}-\d{2}):", section)
    name = re.sub(r" \(measured on [^)]*\)$", "", room[0])
    name += f" (measured on {dated.group(1)}: this run had no Blender)" if dated else ""
    cells = dict(zip(heads, room))
    wanted = ["surfels", "receivers", "wall clock s", "device MiB", "host peak MiB", "relMSE against pt"]
    return ["| " + " | ".join([name] + [cells.get(h, "—") for h in wanted]) + " |"]


def farm_table(r, threads):
    """Wall-clock time of the animated Cornell box's 48 frames in one process and as Slurm job arrays on a
    one-node cluster of this machine (tools/farm/local-slurm.sh); None where that cannot start."""
    cluster, tools = r.scratch / "cluster", ROOT / "tools/farm"
    started = subprocess.run([tools / "local-slurm.sh", "start", cluster], capture_output=True, text=True)
    if started.returncode != 0:
        print(f"  farm figures skipped: {started.stderr.strip()}", file=sys.stderr)
        return None
    env = dict(os.environ, SLURM_CONF=str(cluster / "slurm.conf"), IVGI=str(pathlib.Path(r.ivgi).resolve()))
    scene = ["cornell", "--cells", "26", "--frames", "0-47", "--size", "320x240", "--format", "exr"]
    try:
        def timed(command, cwd, extra_env):
            """Seconds from the command's start to the end of the job it submits (polled often: sbatch
            --wait polls at growing intervals), or of the command itself."""
            work = r.scratch / cwd
            work.mkdir()
            begin = time.monotonic()
            out = subprocess.run(command, cwd=work, env=dict(env, **extra_env), check=True, capture_output=True,
                                 text=True).stdout.strip()
            if command[0] == "sbatch":
                while subprocess.run(["squeue", "-h", "-j", out.split(";")[0]], env=env, capture_output=True,
                                     text=True).stdout.strip():
                    time.sleep(0.05)
                failed = [p for p in work.glob("*.log") if "error" in p.read_text()]
                if failed:
                    sys.exit(f"perf_tables: a farm task failed: {failed[0].read_text()}")
            return time.monotonic() - begin
        rows = []
        one = timed([r.ivgi, "render", *scene, "--out", "frames/f_%04d"], "one", {"LP_NUM_THREADS": str(threads)})
        rows.append(("one process", f"LP_NUM_THREADS={threads}", one))
        for tasks in (1, 2):
            cpus = max(1, threads // tasks)
            seconds = timed(["sbatch", "--parsable", f"--array=0-{tasks - 1}", f"--cpus-per-task={cpus}",
                             tools / "render-array.sbatch", *scene[:1], "frames/f_%04d", *scene[1:]], f"array{tasks}", {})
            rows.append((f"job array, {tasks} task{'s' if tasks > 1 else ''}", f"{cpus} CPU{'s' if cpus > 1 else ''} "
                         f"and LP_NUM_THREADS={cpus} a task", seconds))
    finally:
        subprocess.run([tools / "local-slurm.sh", "stop", cluster], capture_output=True)
    lines = ["| run | threads | wall clock s | frames a second | against one process | 1,000 frames at this rate |",
             "|---|---|---|---|---|---|"]
    for name, how, seconds in rows:
        lines.append(f"| {name} | {how} | {seconds:.1f} | {48 / seconds:.2f} | {one / seconds:.2f}× | "
                     f"{1000 / (48 / seconds) / 60:.1f} min |")
    ratios = [one / seconds for _, _, seconds in rows[1:]]
    per_node = 1000 / (48 / min(seconds for _, _, seconds in rows)) / 60
    lines += ["", f"On one node the array is {min(ratios):.2f}–{max(ratios):.2f}× one process that already uses every core "
                  "(each task pays its start-up and Slurm's scheduling): a farm gains by its nodes. At this rate one "
                  f"node renders a 1,000-frame shot of this scene in about {per_node:.1f} min, N nodes in 1/N of that."]
    return "\n".join(lines)


def cpu_name():
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "unknown CPU"


def replace_between(text, marker, body):
    pattern = re.compile(rf"(<!-- {marker} -->\n).*?(<!-- /{marker} -->)", re.S)
    if not pattern.search(text):
        sys.exit(f"perf_tables: README.md has no <!-- {marker} --> block")
    return pattern.sub(lambda m: m.group(1) + body + "\n" + m.group(2), text)


def machine_line(device, threads):
    return (f"Vulkan device {device['name']} ({device['type']}), driver {device['driver']} "
            f"{device.get('driverInfo', '')}, LP_NUM_THREADS={threads}; pt on {threads} threads; "
            f"CPU {cpu_name()}, {os.cpu_count()} cores")


def error_row(errors):
    """The README headline's row of iv's error against converged pt."""
    return (f"| iv's error against converged pt, `--cells 26`, 320×240, defaults / every surfel a receiver | relMSE "
            f"{errors[('defaults', 1)]:.4f} / {errors[('every_surfel', 1)]:.4f}; at `--supersample 4` "
            f"{errors[('defaults', 4)]:.4f} / {errors[('every_surfel', 4)]:.4f} |")


def frame_rows(columns):
    """The README headline's rows of the animated Cornell box's frame time (per_pass_table's columns)."""
    return [f"| animated Cornell box, `--cells 26` (4,756 surfels), 320×240, defaults | {columns[26]['total']:,.0f} ms "
            f"a frame ({1000.0 / columns[26]['total']:.1f} fps) |",
            f"| the same at `--cells 8` (the default scene) | {columns[8]['total']:.0f} ms a frame "
            f"({1000.0 / columns[8]['total']:.0f} fps) |"]


def replace_rows(text, rows):
    """README.md with each headline row replaced by the new row that starts with its first cell."""
    for row in rows:
        first = row.split(" | ")[0]
        pattern = re.compile(rf"^{re.escape(first)} \|.*$", re.M)
        if not pattern.search(text):
            sys.exit(f"perf_tables: README.md's headline table has no row starting {first!r}")
        text = pattern.sub(lambda m: row, text)
    return text


def equal_rows(ratios):
    """The README headline's rows of iv and ar against pt at equal error (equal_error_table's ratios)."""
    iv = f"{ratios['defaults'][0]:.1f}× / {ratios['every surfel a receiver'][0]:.1f}×"
    iv_flip = f"{ratios['defaults'][1]:.1f}× / {ratios['every surfel a receiver'][1]:.1f}×"
    ar, ar_flip = ratios["ar, defaults"]
    return [f"| iv faster than pt at equal relMSE, defaults / every surfel a receiver | {iv} |",
            f"| iv faster than pt at equal FLIP, defaults / every surfel a receiver | {iv_flip} |",
            f"| ar against pt at equal relMSE / FLIP, defaults | {ar:.1f}× / {ar_flip:.1f}× |"]


def with_rows(table, rows):
    """A section's maker: the body of `table`'s result (its first item) and the README headline rows
    that `rows` makes of the whole result."""
    def make(r, args):
        result = table(r, args)
        return result[0], rows(result)
    return make


# What --only regenerates: each section's table, by the line its body starts with in
# docs/performance.md (the body runs to the next heading), and the README headline rows it feeds.
SECTIONS = {
    "accuracy": ("| iv | relMSE, 1 sample a pixel",
                 with_rows(lambda r, args: accuracy_table(r), lambda result: [error_row(result[1])])),
    "passes": ("| pass | ", with_rows(lambda r, args: per_pass_table(r, args.runs),
                                      lambda result: frame_rows(result[2]))),
    "programs": ("| iv: program |", lambda r, args: (programs_table(r, args.runs), [])),
    "scaling": ("| `--cells` | surfels |", lambda r, args: (scaling_table(r, args.runs), [])),
    "sweep": ("| bins | `--receiver-tol` |", lambda r, args: (sweep_table(r), [])),
    "real": ("| scene | surfels | receivers |", lambda r, args: (real_files_table(r, args.runs), [])),
    "ar": ("| `--dirs` | links |", with_rows(lambda r, args: ar_table(r), lambda result: ar_rows(result[1]))),
    "flicker": ("| setting | mean relMSE of the frames |", lambda r, args: (flicker_table(r), [])),
    "glossy": ("| method | relMSE, 1 sample a pixel |", lambda r, args: (glossy_table(r, args.runs), [])),
    "size": ("| scene | surfels | method | ms per frame |", lambda r, args: (size_table(r), [])),
    "equal": ("| setting | ms per frame | relMSE | pt ms",
              with_rows(lambda r, args: equal_error_table(r, args.runs), lambda result: equal_rows(result[2]))),
}


def device_of(r):
    """The Vulkan device `r`'s ivgi renders on, as its sidecar names it."""
    return r.json("render", "cornell", "--method", "none", "--size", "16x12", "--frames", 0, "--format", "exr",
                  "--out", r.scratch / "device_%04d")["device"]


def replace_section(path, marker, body, note):
    """Puts `body`, then `note`, in place of the section of `path` that starts at `marker` (up to the
    next section, or the end)."""
    doc = path.read_text()
    start = doc.index(marker)
    end = doc.find("\n## ", start)
    end = len(doc.rstrip("\n")) if end < 0 else end
    path.write_text(doc[:start] + body + "\n\n" + note + "\n" + doc[end:].rstrip("\n") + "\n")


def regenerate_section(args):
    """--only SECTION: that section's body in docs/performance.md (and the README headline rows it
    feeds), with a line naming the machine and date it was measured on."""
    marker, make = SECTIONS[args.only]
    with tempfile.TemporaryDirectory(prefix="ivgi-perf-") as scratch:
        r = Runner(args.ivgi, args.threads, scratch)
        body, rows = make(r, args)
        device = device_of(r)
    path = DOCS / "performance.md"
    note = (f"This section alone was regenerated (`tools/perf_tables.py --only {args.only}`) on "
            f"{datetime.date.today().isoformat()}: {machine_line(device, args.threads)}.")
    replace_section(path, marker, body, note)
    if rows:
        readme = ROOT / "README.md"
        readme.write_text(replace_rows(readme.read_text(), rows))
    print(f"wrote the {args.only} section of {path}", file=sys.stderr)


def bring_up_to_date(ivgi):
    """The tables must be the sources' figures: the default binary is built first (nothing to do
    where it is up to date), and uncommitted changes to what it is built from are named on stderr.
    A binary given with --ivgi (a portable bundle, another build) is taken as it is."""
    if pathlib.Path(ivgi).resolve() != (ROOT / "build/ivgi").resolve():
        return
    subprocess.run(["cmake", "--build", str(ROOT / "build"), "-j", str(os.cpu_count() or 1)], check=True,
                   stdout=subprocess.DEVNULL)
    changed = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "engine", "shaders", "scenes"],
                             capture_output=True, text=True).stdout
    if changed.strip():
        print("perf_tables: these sources differ from the last commit; the figures will be theirs:\n" + changed,
              file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ivgi", default=ROOT / "build/ivgi")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--only", choices=sorted(SECTIONS), help="regenerate this section alone")
    args = parser.parse_args()
    bring_up_to_date(args.ivgi)
    if args.only:
        return regenerate_section(args)
    with tempfile.TemporaryDirectory(prefix="ivgi-perf-") as scratch:
        r = Runner(args.ivgi, args.threads, scratch)
        print("per-pass times", file=sys.stderr)
        passes, device, columns = per_pass_table(r, args.runs)
        print("per-program times", file=sys.stderr)
        programs = programs_table(r, args.runs)
        print("scaling", file=sys.stderr)
        scaling = scaling_table(r, args.runs)
        print("sweep", file=sys.stderr)
        sweep = sweep_table(r)
        print("equal error", file=sys.stderr)
        equal, reference_s, ratios, _ = equal_error_table(r, args.runs)
        print("ar", file=sys.stderr)
        ar, ar_figures = ar_table(r)
        print("accuracy", file=sys.stderr)
        accuracy, errors = accuracy_table(r)
        print("flicker", file=sys.stderr)
        flicker = flicker_table(r)
        print("glossy", file=sys.stderr)
        glossy = glossy_table(r, args.runs)
        print("real files", file=sys.stderr)
        real = real_files_table(r, args.runs)
        print("size", file=sys.stderr)
        size = size_table(r)
        print("render farm", file=sys.stderr)
        farm = farm_table(r, args.threads)

    machine = machine_line(device, args.threads)
    today = datetime.date.today().isoformat()
    doc = f"""# Performance

Generated by `tools/perf_tables.py` on {today}; rerun it to refresh every table and figure here,
the sweep's plot and CSV, and the headline table of the README. Timings are GPU milliseconds
(timestamps around each pass), medians over {args.runs} runs of `ivgi bench`, each itself the median
over its frames after warm-up frames.

Machine: {machine}. The same solvers on a discrete GPU: [performance-gpu.md](performance-gpu.md)
(`tools/gpu_tables.py`).

## Per pass: the animated Cornell box

`ivgi bench cornell --cells N --size 320x240 --frames 20 --warmup 3` at the defaults (6×16×16
bins, ε 0.02, bounces until converged, receivers at `--receiver-tol 0.4`, surfaces tessellated to
1/16 of the scene: `--cells 8` is sampled as about 16; the lamp's direct light per pixel from 128
points' depth maps of 128², `--direct pixels`). What cannot move (the room, the tall block)
is linked and pruned in the first frame, and drawn into the maps once; every frame after it draws
the moving block into the maps over them (`direct light`), draws the camera's view (`raster`) and
marks the surfels the image reads (`shown`: the receivers are judged at `--unseen-tol` elsewhere),
links the moving block, chooses its receivers, prunes them and solves; `direct pixels` gives each
pixel its share of the lamp's points.

{passes}

## Per program: where a frame's time goes

{PROGRAMS_INTRO}

{programs}

## Cost against the scene's tessellation

The same scene at more cells a side (frames after 2 warm-up frames: 10, 10, 5, 3), with adaptive
receivers (`--receiver-tol 0.4`, the default here), and with every surfel a receiver
(`--receiver-tol 0`, the default on a GPU).

{scaling}

## Speed against accuracy

`ivgi sweep cornell --cells 26 --reference REF --supersample 4 --method iv,ar --bins 8,16,24,32
--receiver-tol 0,0.1,0.2,0.4,0.8 --dirs 2,4,6,8 --repeats 3`: frame 0 at 320×240 against the
4096-spp pt reference of *ar on the animated Cornell box* below, each setting solving the frame as
a later frame of the animation does, bounces (iterations) until converged; every row is in
[sweep_cornell.csv](sweep_cornell.csv). Each pixel averages 4×4 samples, as pt's pixel averages its
paths: at one sample a pixel the edges alias against the reference, which adds an error no setting
changes (*Where iv's error lies*). The plot joins each series' front: iv with every surfel a
receiver (the solver before adaptive receivers), iv with adaptive receivers, and ar (antiradiance)
at each `--dirs`.

![error against GPU time per frame, each series' Pareto front joined](sweep_cornell.png)

{sweep}

## ar on the animated Cornell box

`ivgi bench cornell --cells 26 --size 320x240 --method ar --dirs N`, and frame 0 rendered the same
way against pt at 4096 spp (defaults: `--dirs 4`, iterations until an iteration changes the
irradiance by less than 0.001, chains of 16 frames). Every frame relinks the moving block (the links
between static objects are made once). A restart (`--restart-every 1`, 3 frames after a warm-up
frame) starts from the emission alone; by default frames 0, 16, 32, … do, and each frame between
starts from the solution of the frame before (48 frames, the whole animation, after a warm-up
frame: 3 restarts). Frame 0 starts a chain, so its relMSE is the restart's; the chained frames'
accuracy over a sequence is in *Flicker*.

{ar}

## Where iv's error lies

Frame 0 of the animated Cornell box at `--cells 26`, 320×240, against the 4096-spp pt reference
above, rendered at one sample a pixel (the default) and at `--supersample 4`; a pt pixel averages
its paths over the pixel, so at one sample a pixel the error includes the edges' aliasing. Each
image is `ivgi compare --ratio` of the 4×4 render: test / reference per pixel, blue darker and red
brighter, saturating at ±25 %, grey where they agree (the reference's noise speckles it). What
stays structured is iv's bias ([notes/iv-accuracy-history.md](notes/iv-accuracy-history.md)). Below, the closed furnace
(`ivgi scene furnace --cells 12 --albedo ρ --emission 1`) rendered at defaults at 160×120.

{accuracy}

## iv and ar against the path tracer at equal error

`ivgi bench --equal-error --size 320x240 --reference REF [--method ar]`: the solver's mean GPU
time over 20 animated frames (ar: one restart among them) and its relMSE on frame 0 against a
4096-spp pt reference (which took
{reference_s:,.0f} s to render); pt renders the frame at 1, 2, 4, … spp on {args.threads} threads until it
reaches the solver's relMSE, and its wall-clock time at that error is interpolated log–log. iv and
ar run on lavapipe, a CPU emulating a GPU, on the same cores as pt.

{equal}

## Flicker

The animated Cornell box's frames 0–11 at `--cells 26`, 160×120, against pt at 1024 spp:
`ivgi compare` gives each frame's relMSE and the sequence's temporal relMSE (the error of the
frame-to-frame change, where the surfaces stay put; pt's own noise is in both figures).

{flicker}

## Glossy surfaces

{GLOSSY_INTRO}

{glossy}

## Real files

One frame at 480×270 at the defaults, the median wall clock of {args.runs} renders from the command's start (pipelines compiled,
links made, every receiver pruned), and its relMSE against pt at 1024 spp with the same light (the
engine has none: both are lit by the default white sky).

{real}

## When each method pays: cost against the scene's size at equal error

{SIZE_INTRO}

{size}

## Render farms: a Slurm job array on one node

The animated Cornell box at `--cells 26`, its 48 frames at 320×240 with iv's defaults, written as
EXR: wall-clock time (scheduling included) in one process, and as a job array of
`tools/farm/render-array.sbatch` on a one-node Slurm cluster of this machine
(`tools/farm/local-slurm.sh`), one shard a task. Each task starts its own process: it compiles the
pipelines and makes the static links again.

{farm if farm else "Not measured on this run: starting the local cluster needs root and Debian's slurm-wlm and munge."}
"""
    (DOCS / "performance.md").write_text(doc)

    headline = "\n".join([
        "| figure | value |",
        "|---|---|",
        *frame_rows(columns),
        error_row(errors),
        *equal_rows(ratios),
        *ar_rows(ar_figures),
    ])
    readme = ROOT / "README.md"
    readme.write_text(replace_between(readme.read_text(), "perf:headline", headline))
    print(f"wrote {DOCS / 'performance.md'} and the README's headline table", file=sys.stderr)


if __name__ == "__main__":
    main()
