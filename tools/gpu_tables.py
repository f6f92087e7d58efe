#!/usr/bin/env python3
"""Regenerates docs/performance-gpu.md: the GPU-timed figures of docs/performance.md on whatever
Vulkan device ivgi picks (a discrete GPU before an integrated one, before lavapipe).

Usage: tools/gpu_tables.py [--ivgi build/ivgi] [--runs 3] [--references DIR] [--scenes FILE ...]
                           [--out docs/performance-gpu.md] [--only TITLE]

Only the GPU solvers run here; pt is not timed. Errors are measured against pt references rendered
beforehand, wherever, into --references: `cornell26_pt_0000.exr` (the animated Cornell box at
`--cells 26`, 320×240, 4096 spp) and `STEM_pt_0000.exr` for each --scenes file (480×270, 1024 spp).
A row whose reference is missing shows no error. Each section is written as soon as it is measured,
so a run cut short keeps what it finished. The sweep's plot goes beside --out as
sweep_cornell_gpu.png (it needs a python3 with matplotlib: IVGI_PYTHON names one, else the one
running this script).

On a GPU machine without ivgi's Debian libraries, `tools/portable_bundle.py --out DIR` packs ivgi
with what it loads: run this script with `--ivgi DIR/ivgi` and LD_LIBRARY_PATH=DIR/lib.
"""
import argparse
import datetime
import json
import os
import pathlib
import shutil
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from perf_tables import (DOCS, PROGRAMS_INTRO, ROOT, Runner, cpu_name, device_of, fmt, median,  # noqa: E402
                         per_pass_table, programs_table, replace_section, scaling_table, sweep_markdown)


def relmse(r, test, reference):
    if not reference.exists():
        return None
    return r.json("compare", test, reference)["frames"][0]["metrics"]["relMSE"]


def error(value):
    return "—" if value is None else f"{value:.4f}"


def cornell_error(r, references, *options):
    """Frame 0 of the animated Cornell box at --cells 26, 320×240, with `options`: its relMSE against
    the pt reference (None where there is none)."""
    out = r.scratch / f"cornell_{r.count}"
    r.run("render", "cornell", "--cells", 26, "--size", "320x240", "--frames", 0, "--format", "exr", "--out",
          out / "f_%04d", *options)
    return relmse(r, out / "f_0000.exr", references / "cornell26_pt_0000.exr")


def ar_table(r, runs, references):
    """ar at --cells 26, 320×240: restarts (every frame from the emission) per --dirs, and the default
    chains over the whole animation (mean frame time)."""
    lines = ["| setting | links | iterations | global ms | frame ms | fps | relMSE frame 0 |",
             "|---|---|---|---|---|---|---|"]
    for dirs, chained in ((2, False), (4, False), (8, False), (2, True), (4, True)):
        extra = ("--method", "ar", "--dirs", dirs) + (() if chained else ("--restart-every", 1))
        frames = 48 if chained else 6
        results = [r.json("bench", "cornell", "--cells", 26, "--size", "320x240", "--frames", frames, "--warmup", 1,
                          *extra) for _ in range(runs)]
        key = "meanMs" if chained else "medianMs"
        total = median([j["passes"]["total"][key] for j in results])
        glob = median([j["passes"]["global"]["medianMs"] for j in results])
        iterations = sorted(f["solver"]["iterations"] for f in results[-1]["frames"])
        rel = None if chained else cornell_error(r, references, *extra)
        name = f"`--dirs {dirs}`" + (", chains of 16 (mean)" if chained else ", restarts") + \
            (" (default)" if dirs == 4 and chained else "")
        lines.append(f"| {name} | {results[-1]['solver']['links']:,} | {median(iterations):.0f} | {fmt(glob)} | "
                     f"{fmt(total)} | {1000.0 / total:.1f} | {error(rel) if not chained else 'as a restart'} |")
    return "\n".join(lines)


def sweep_table(r, references, plot):
    """The speed/accuracy front at 4×4 samples a pixel, as in performance.md: its plot copied to `plot`."""
    reference = references / "cornell26_pt_0000.exr"
    if not reference.exists():
        return "Not measured: no pt reference `cornell26_pt_0000.exr`."
    out = r.scratch / "sweep"
    r.run("sweep", "cornell", "--cells", 26, "--reference", reference, "--supersample", 4, "--method", "iv,ar",
          "--bins", "8,16,24,32", "--receiver-tol", "0,0.2,0.4", "--dirs", "2,4,8", "--repeats", 3, "--out", out)
    shutil.copy(out / "sweep.png", plot)
    return f"![error against GPU time per frame, each series' Pareto front joined]({plot.name})\n\n" + \
        sweep_markdown(out / "sweep.csv")


def solve(figures):
    """How the frame's solver ended, from its sidecar figures."""
    if "bounces" in figures:
        return f"{figures['bounces']:.0f} bounces"
    damped = f", damped to {figures['damping']:g}" if figures.get("damping", 1) < 1 else ""
    if figures.get("diverged"):
        return f"diverged: shows iteration {figures['iterations']:.0f}{damped}"
    return f"{figures['iterations']:.0f} iterations{damped}"


def real_files_table(r, scenes, references, runs):
    """One frame at 480×270 at the defaults per method (iv's: every surfel a receiver), and iv with
    adaptive receivers (lavapipe's default): the median wall clock of `runs` renders from the
    command's start (device opened, pipelines compiled, links made; the driver's cache of compiled
    pipelines warms on the first), the frame's GPU time and its error against pt."""
    lines = ["| scene | method | wall clock s | GPU ms | solve | relMSE against pt |", "|---|---|---|---|---|---|"]
    settings = (("iv", ()), ("iv, adaptive receivers", ("--receiver-tol", 0.4)), ("ar", ("--method", "ar")))
    for path in scenes:
        for index, (name, extra) in enumerate(settings):
            out = r.scratch / f"{path.stem}_{index}"
            walls = []
            for _ in range(runs):
                begin = time.monotonic()
                r.run("render", path, *extra, "--frames", 0, "--size", "480x270", "--format", "exr", "--out",
                      out / "f_%04d")
                walls.append(time.monotonic() - begin)
            seconds = median(walls)
            frame = json.loads((out / "f.json").read_text())["frames"][0]
            rel = relmse(r, out / "f_0000.exr", references / f"{path.stem}_pt_0000.exr")
            lines.append(f"| {path.name} | {name} | {seconds:.2f} | {fmt(frame['totalGpuMs'])} | "
                         f"{solve(frame['solver'])} | {error(rel)} |")
    return "\n".join(lines)


def animated_table(r, scenes, runs):
    """Each file's frames after the first at 480×270, iv and ar at the defaults: medians over `runs`
    runs of `bench --frames 10 --warmup 2`, each itself the median frame, with its costliest passes."""
    lines = ["| scene | method | frame ms | fps | the costliest passes, ms |", "|---|---|---|---|---|"]
    for path in scenes:
        for method in ("iv", "ar"):
            results = [r.json("bench", path, "--method", method, "--size", "480x270", "--frames", 10, "--warmup", 2)
                       for _ in range(runs)]
            times = {p: median([j["passes"][p]["medianMs"] for j in results])
                     for p in results[0]["passes"] if p != "total"}
            total = median([j["passes"]["total"]["medianMs"] for j in results])
            costliest = ", ".join(f"{p} {fmt(times[p])}" for p in sorted(times, key=lambda p: -times[p])[:3])
            lines.append(f"| {path.name} | {method} | {fmt(total)} | {1000.0 / total:.1f} | {costliest} |")
    return "\n".join(lines)


def later_sections(r, args):
    """The sections after the per-pass one: (title, intro, a function that measures the table)."""
    return (
        ("Per program: where a frame's time goes", PROGRAMS_INTRO, lambda: programs_table(r, args.runs)),
        ("Real files", "One frame at 480×270 at the defaults (iv: every surfel a receiver), and iv with "
         "adaptive receivers (`--receiver-tol 0.4`, lavapipe's default); the wall clock is the median "
         "of the runs' renders; the engine is lit by the default white sky.",
         lambda: real_files_table(r, args.scenes, args.references, args.runs)),
        ("Real files, frame after frame",
         "`ivgi bench FILE --size 480x270 --frames 10 --warmup 2 --method M` at the defaults: the "
         "frames after the first, where what stands still is kept from frame to frame (the engine "
         "has no animation: its frames redo what depends on the view).",
         lambda: animated_table(r, args.scenes, args.runs)),
        ("ar on the animated Cornell box",
         "`ivgi bench cornell --cells 26 --size 320x240 --method ar --dirs N`, 6 frames after a warm-up "
         "frame each from the emission (`--restart-every 1`), and the default chains over the 48 frames "
         "of the animation; frame 0's relMSE against pt at 4096 spp.",
         lambda: ar_table(r, args.runs, args.references)),
        ("Speed against accuracy",
         "`ivgi sweep cornell --cells 26 --reference REF --supersample 4 --method iv,ar --bins 8,16,24,32 "
         "--receiver-tol 0,0.2,0.4 --dirs 2,4,8 --repeats 3`: frame 0 at 320×240, 4×4 samples a pixel, "
         "against the pt reference at 4096 spp, as in performance.md.",
         lambda: sweep_table(r, args.references, args.out.parent / "sweep_cornell_gpu.png")),
        ("iv's cost against the scene's tessellation",
         "As in performance.md: frames after 2 warm-up frames, with adaptive receivers "
         "(`--receiver-tol 0.4`) and with every surfel a receiver (`--receiver-tol 0`, the default "
         "here).", lambda: scaling_table(r, args.runs, every_most=100)))


def machine_line(device):
    return (f"Vulkan device {device['name']} ({device['type']}), driver {device['driver']} "
            f"{device.get('driverInfo', '')}; CPU {cpu_name()}, {os.cpu_count()} cores")


def regenerate_section(r, args):
    """Measures the section titled args.only again and puts it in place of its table in args.out."""
    title, intro, make = next(t for t in later_sections(r, args) if t[0] == args.only)
    body = f"## {title}\n\n{intro}\n\n{make()}"
    note = (f"This section alone was regenerated (`tools/gpu_tables.py --only '{title}'`) on "
            f"{datetime.date.today().isoformat()}: {machine_line(device_of(r))}.")
    replace_section(args.out, f"## {title}\n", body, note)
    print(f"wrote the section '{title}' of {args.out}", file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ivgi", default=ROOT / "build/ivgi")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--references", type=pathlib.Path, default=pathlib.Path("gpu-references"))
    parser.add_argument("--scenes", type=pathlib.Path, nargs="*", default=[])
    parser.add_argument("--out", type=pathlib.Path, default=DOCS / "performance-gpu.md")
    parser.add_argument("--only", help="the title of a section after the first: measure it alone into --out")
    args = parser.parse_args()
    sections = []

    def write(device):
        body = "\n\n".join(sections)
        args.out.write_text(f"""# Performance on a GPU

Generated by `tools/gpu_tables.py` on {datetime.date.today().isoformat()}; the lavapipe figures,
the sweep and pt are in [performance.md](performance.md). Timings are GPU milliseconds (timestamps
around each pass), medians over {args.runs} runs of `ivgi bench`, each itself the median over its
frames after warm-up frames. Errors are against pt references rendered beforehand with the same
settings (`--references`): pt is not run on this machine.

Machine: {machine_line(device)}.

{body}
""")

    with tempfile.TemporaryDirectory(prefix="ivgi-gpu-") as scratch:
        # The sweep plots with this interpreter unless told otherwise: a GPU machine's python3 is
        # seldom Debian's, whose matplotlib ivgi looks for first.
        os.environ.setdefault("IVGI_PYTHON", sys.executable)
        r = Runner(args.ivgi, os.cpu_count(), scratch)
        if args.only:
            return regenerate_section(r, args)
        passes, device, _ = per_pass_table(r, args.runs)
        rel = cornell_error(r, args.references)
        sections.append("## iv, per pass: the animated Cornell box\n\n`ivgi bench cornell --cells N --size 320x240 "
                        "--frames 20 --warmup 3` at the defaults (on a GPU, every surfel a receiver). relMSE of "
                        f"frame 0 at `--cells 26` against pt at 4096 spp: {error(rel)}.\n\n{passes}")
        write(device)
        for title, intro, make in later_sections(r, args):
            print(title, file=sys.stderr, flush=True)
            sections.append(f"## {title}\n\n{intro}\n\n{make()}")
            write(device)
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
