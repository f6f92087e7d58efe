#!/usr/bin/env python3
"""Packs build/ivgi into a folder that runs on an x86-64 Linux machine with a Vulkan loader and
driver but without ivgi's Debian libraries (a GPU machine that runs tools/gpu_tables.py, say).

Usage: tools/portable_bundle.py [--ivgi build/ivgi] --out DIR
Then, there: LD_LIBRARY_PATH=DIR/lib DIR/ivgi ...

The libraries ivgi links are copied (OpenImageIO and its EXR and PNG readers and writers,
tinygltf, SPIRV-Cross, meshoptimizer, TBB, Embree: the loader casts rays for the backs of open
surfaces, the path tracer for everything), whatever they are: a stub in their place would answer
ivgi's own calls with zeros. The rest of what they link, the codecs of formats ivgi never reads or
writes, would bring hundreds of MB; each becomes a stub of the same name defining, with their
versions, the symbols the bundle imports from it, whose functions return a pointer to zeros
(OpenImageIO calls some at start-up: registrations, version strings). The C and C++ runtimes and
the Vulkan loader are the machine's. The bundle is about 70 MB, 15 MB as a tar.xz.
"""
import argparse
import pathlib
import re
import shutil
import subprocess
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
LIBDIR = pathlib.Path("/lib/x86_64-linux-gnu")
THE_MACHINES = {"libc.so.6", "libm.so.6", "libstdc++.so.6", "libgcc_s.so.1", "ld-linux-x86-64.so.2",
                "libpthread.so.0", "libdl.so.2", "librt.so.1", "libvulkan.so.1"}
COPIED = {"libOpenImageIO.so.2.4", "libOpenImageIO_Util.so.2.4", "libOpenEXR-3_1.so.30", "libOpenEXRCore-3_1.so.30",
          "libIlmThread-3_1.so.30", "libIex-3_1.so.30", "libImath-3_1.so.29", "libpng16.so.16", "libjpeg.so.62",
          "libz.so.1", "libtbb.so.12", "libboost_thread.so.1.74.0", "libspirv-cross-c-shared.so.0",
          "libtinygltf.so.2d", "libstb.so.0"}


def readelf(*args):
    return subprocess.run(["readelf", *map(str, args)], capture_output=True, text=True, check=True).stdout


def needed(path):
    return re.findall(r"\(NEEDED\).*\[(.*)\]", readelf("-d", path))


def imported(path):
    """The names of the dynamic symbols `path` leaves undefined."""
    names = set()
    for line in readelf("--dyn-syms", "-W", path).splitlines():
        f = line.split()
        if len(f) >= 8 and f[6] == "UND":
            names.add(f[7].split("@")[0])
    return names


def stub(name, wanted, out, work):
    """Writes out/name: a library of soname `name` defining the symbols of `wanted` that the real
    one defines, with their versions."""
    real = (LIBDIR / name).resolve()
    definitions = re.search(r"Version definition section.*?(?=\n\n|\Z)", readelf("-V", "-W", real), re.S)
    nodes = [m.group(1) for m in re.finditer(r"Name: (\S+)", definitions.group(0) if definitions else "")
             if m.group(1) != name and not m.group(1).startswith("lib")]
    asm = [".bss", "zeros: .zero 4096"]
    for n, line in enumerate(readelf("--dyn-syms", "-W", real).splitlines()):
        f = line.split()
        if len(f) < 8 or not f[0].endswith(":") or f[6] in ("UND", "ABS") or f[4] not in ("GLOBAL", "WEAK"):
            continue
        kind, size, full = f[3], int(f[2], 0), f[7]
        symbol, separator, version = re.match(r"([^@]+)(@@|@)?(.*)", full).groups()
        if symbol not in wanted:
            continue
        versioned = separator and version in nodes
        label = f"s{n}" if versioned else symbol
        if kind in ("OBJECT", "TLS"):
            section = ".bss" if kind == "OBJECT" else '.section .tbss,"awT",@nobits'
            asm += [section, f".globl {label}", f".type {label},@{'object' if kind == 'OBJECT' else 'tls_object'}",
                    f".size {label},{size}", f"{label}: .zero {max(size, 1)}"]
        else:
            asm += [".text", f".globl {label}", f".type {label},@function", f"{label}:", "lea zeros(%rip), %rax", "ret"]
        if versioned:
            asm.append(f".symver {label}, {symbol}{separator}{version}, remove")
    source, script = work / f"{name}.s", work / f"{name}.map"
    source.write_text("\n".join(asm) + "\n")
    command = ["gcc", "-shared", "-nostdlib", "-o", out / name, source, f"-Wl,-soname,{name}"]
    if nodes:
        script.write_text("".join(f"{v} {{ }};\n" for v in nodes))
        command.append(f"-Wl,--version-script={script}")
    subprocess.run(list(map(str, command)), check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ivgi", type=pathlib.Path, default=ROOT / "build/ivgi")
    parser.add_argument("--out", type=pathlib.Path, required=True)
    args = parser.parse_args()
    lib = args.out / "lib"
    lib.mkdir(parents=True, exist_ok=True)
    subprocess.run(["strip", "-o", str(args.out / "ivgi"), str(args.ivgi)], check=True)
    todo, seen, stubs, wanted = [args.ivgi], set(), [], set()
    while todo:
        path = todo.pop()
        wanted |= imported(path)
        for name in needed(path):
            if name in seen or name in THE_MACHINES:
                continue
            seen.add(name)
            if name in COPIED or path == args.ivgi:
                shutil.copy(LIBDIR / name, lib / name)
                todo.append(LIBDIR / name)
            else:
                stubs.append(name)
    with tempfile.TemporaryDirectory() as work:
        for name in stubs:
            stub(name, wanted, lib, pathlib.Path(work))
    print(f"{args.out}: ivgi, {len(seen) - len(stubs)} libraries copied, {len(stubs)} stubbed: {' '.join(stubs)}")


if __name__ == "__main__":
    main()
