#!/usr/bin/env python3
"""Golden buffers: every method on every backend that implements it (`stsv info --methods`), on
fence, foliage, knot and tests/data/scene/example.json, 48x36, 32 samples, seed 7, with Vulkan
validation on. A per-sample method's light-sample buffers (--dump-ls) in every kind it writes
(bitmask, counters, transmittance); a method without per-sample answers, its float visibility
image (--visibility) with the bitmask buffer and, where it accepts one, the transmittance buffer.

    golden.py record STSV              render and write tests/golden/record.tar.xz
    golden.py compare STSV IMAGES_DIR  render again and compare with the record byte for byte

The record holds the files' bytes (xz-compressed), not digests: a failure names each file that
changed, how many samples and pixels differ, and writes a heat image into IMAGES_DIR (a failed CI
run keeps it): per pixel the differing samples (bits of a bitmask), or the |difference| of a
float image.

One record holds on every x86-64 machine: Embree's kernels differ in rounding from one instruction
set to another, so the renders pin them to SSE2 (STSV_EMBREE_CONFIG=isa=sse2), which every x86-64
CPU runs; llvmpipe compiles the shaders for the CPU's features, fusing multiply-adds where it has
FMA (VSM's visibility differs without), so its features are pinned to SSE2 too
(GALLIUM_OVERRIDE_CPU_CAPS=sse2); the library is built without floating-point contraction
(-ffp-contract=off, CMakeLists.txt), so no compiler flag that enables FMA changes the CPU
mirror's rounding.

One exception compares within a stated tolerance instead of byte for byte: pw's and pw+stsv's
visibility on Vulkan, whose wedge coverage is summed by additive blending in the order the compute
passes append the hulls, which varies from run to run (GPU_SUMMED).
"""
import ast
import io
import json
import lzma
import os
import struct
import subprocess
import sys
import tarfile
import tempfile
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
RECORD = HERE / "record.tar.xz"
SCENES = ["fence", "foliage", "knot", str(SOURCE / "tests/data/scene/example.json")]
COMMON = ["--size", "48x36", "--samples", "32", "--seed", "7", "-q"]
PINNED = {"STSV_EMBREE_CONFIG": "isa=sse2", "GALLIUM_OVERRIDE_CPU_CAPS": "sse2", "STSV_VALIDATION": "1"}
# Float visibility summed in a run-dependent order: |difference| allowed. The coverage of at most
# a few dozen wedges per pixel, each at most 1, summed in float32 in any order: a few units of the
# last place of a value of at most 1 (2^-24 each); 1e-5 is about 170 of them.
GPU_SUMMED = {("pw", "vulkan"), ("pw+stsv", "vulkan")}
SUMMED_TOLERANCE = 1e-5


def run(args, env):
    return subprocess.run(args, env=env, capture_output=True, text=True)


def render_all(stsv, out):
    """Renders every golden file into `out`; returns {file name: (method, backend)}."""
    env = dict(os.environ, **PINNED)
    pairs = [line.split() for line in run([stsv, "info", "--methods"], env).stdout.splitlines() if line.strip()]
    if not pairs:
        sys.exit(f"golden: `{stsv} info --methods` listed no method")
    prefixes = {}
    total = len(pairs) * len(SCENES)
    done = 0
    for method, backend in pairs:
        for scene in SCENES:
            done += 1
            print(f"golden: [{done}/{total}] {method} {backend} {Path(scene).stem}", file=sys.stderr, flush=True)
            name = f"{Path(scene).stem}_{method.replace('+', '_')}_{backend}"
            prefixes[name + "_"] = (method, backend)
            base = [stsv, "render", scene, "--method", method, "--backend", backend] + COMMON
            for buffer in ["bitmask", "counters", "transmittance"]:
                path = out / f"{name}_{buffer}.npy"
                r = run(base + ["--buffer", buffer, "--dump-ls", str(path)], env)
                if "no per-sample answer" in r.stderr:
                    if buffer == "counters":
                        continue  # a visibility image does not depend on it
                    path = out / f"{name}_{buffer}_visibility.npy"
                    r = run(base + ["--buffer", buffer, "--visibility", str(path)], env)
                if "does not write" in r.stderr:
                    continue  # the method refuses this buffer kind: nothing to hold
                if "vulkan validation" in r.stderr:
                    sys.exit(f"golden: Vulkan validation messages from {' '.join(base)} --buffer {buffer}:\n{r.stderr}")
                if r.returncode != 0:
                    sys.exit(f"golden: {' '.join(base)} --buffer {buffer} failed:\n{r.stderr}")
    # Each file's method and backend: the longest prefix it starts with (pw_ is also pw_stsv_'s).
    owners = {}
    for f in out.iterdir():
        matches = [p for p in prefixes if f.name.startswith(p)]
        owners[f.name] = prefixes[max(matches, key=len)] if matches else None
    return owners


def read_npy(data):
    """(dtype descr, shape, payload bytes) of a .npy file's bytes."""
    if data[:6] != b"\x93NUMPY":
        raise ValueError("not a .npy file")
    major = data[6]
    length_size = 2 if major == 1 else 4
    (header_len,) = struct.unpack("<H" if major == 1 else "<I", data[8:8 + length_size])
    header = ast.literal_eval(data[8 + length_size:8 + length_size + header_len].decode("latin1"))
    return header["descr"], tuple(header["shape"]), data[8 + length_size + header_len:]


def values(descr, payload):
    if descr == "|u1":
        return list(payload)
    fmt = {"<f2": "e", "<f4": "f", "<u2": "H", "<u4": "I"}[descr]
    return list(struct.unpack("<" + fmt * (len(payload) // struct.calcsize(fmt)), payload))


def per_pixel_differences(name, old, new):
    """((width, height, differing samples per pixel), largest |difference|, why not comparable):
    bits for a bitmask buffer, values otherwise."""
    descr, shape, a = read_npy(old)
    descr2, shape2, b = read_npy(new)
    if (descr, shape) != (descr2, shape2):
        return None, 0.0, f"layout changed: {descr} {shape} -> {descr2} {shape2}"
    height, width = shape[0], shape[1]
    va, vb = values(descr, a), values(descr, b)
    step = max(1, len(va) // max(1, height * width))
    bits = "_bitmask" in name and not name.endswith("_visibility.npy")
    counts = [0] * (height * width)
    heat = [0.0] * (height * width)  # differing samples, or the |difference| of a float image
    largest = 0.0
    for i, (x, y) in enumerate(zip(va, vb)):
        if x == y:
            continue
        pixel = min(i // step, len(counts) - 1)
        n = bin(x ^ y).count("1") if bits else 1
        counts[pixel] += n
        if isinstance(x, float):
            largest = max(largest, abs(x - y))
            heat[pixel] += abs(x - y)
        else:
            heat[pixel] += n
    return (width, height, counts, heat), largest, ""


def write_png(path, width, height, counts, scale=6):
    """A heat image of the differences per pixel: black none, red to yellow more (relative to
    the largest)."""
    peak = max(counts) or 1
    rows = []
    for y in range(height):
        row = bytearray([0])
        for x in range(width):
            c = counts[y * width + x]
            t = c / peak
            pixel = bytes([0, 0, 0]) if c == 0 else bytes([255, int(255 * t), 0])
            row += pixel * scale
        rows.extend([bytes(row)] * scale)
    raw = b"".join(rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width * scale, height * scale, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    path.write_bytes(png)


def record(stsv):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        render_all(stsv, out)
        buffer = io.BytesIO()
        with tarfile.open(fileobj=buffer, mode="w:xz", preset=9 | lzma.PRESET_EXTREME) as tar:
            for f in sorted(out.iterdir()):
                info = tarfile.TarInfo(f.name)
                info.size = f.stat().st_size
                info.mtime = 0
                tar.addfile(info, f.open("rb"))
        RECORD.write_bytes(buffer.getvalue())
        print(f"golden: recorded {len(list(out.iterdir()))} files in {RECORD} ({RECORD.stat().st_size} bytes)")


def compare(stsv, images):
    if not RECORD.exists():
        sys.exit(f"golden: no record {RECORD}; make one with: {sys.argv[0]} record {stsv}")
    with tarfile.open(RECORD, "r:xz") as tar:
        recorded = {m.name: tar.extractfile(m).read() for m in tar.getmembers()}
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        owners = render_all(stsv, out)
        now = {f.name: f.read_bytes() for f in out.iterdir()}
    failures = []
    tolerated = 0
    for name in sorted(set(recorded) | set(now)):
        if name not in now:
            failures.append(f"{name}: recorded, no longer written")
            continue
        if name not in recorded:
            failures.append(f"{name}: written, not in the record")
            continue
        if recorded[name] == now[name]:
            continue
        diff, largest, why = per_pixel_differences(name, recorded[name], now[name])
        if diff is None:
            failures.append(f"{name}: {why}")
            continue
        width, height, counts, heat = diff
        summed = owners.get(name) in GPU_SUMMED and name.endswith("_visibility.npy")
        if summed and largest <= SUMMED_TOLERANCE:
            tolerated += 1
            continue
        images.mkdir(parents=True, exist_ok=True)
        image = images / f"golden_{Path(name).stem}.png"
        write_png(image, width, height, heat)
        pixels = sum(1 for c in counts if c)
        failures.append(f"{name}: {sum(counts)} samples differ in {pixels} of {width * height} pixels"
                        + (f", largest |difference| {largest:.3g}" if largest else "") + f"; image {image}")
    if failures:
        print("golden: FAIL: the buffers below differ from tests/golden/record.tar.xz:", file=sys.stderr)
        for f in failures:
            print("  " + f, file=sys.stderr)
        print("If the change is meant to alter results, re-record and say why in the commit:\n"
              f"  python3 tests/golden/golden.py record {stsv}", file=sys.stderr)
        sys.exit(1)
    print(f"golden: all {len(now)} buffers as recorded ({tolerated} summed visibility images within "
          f"{SUMMED_TOLERANCE:g}, the rest byte for byte)")


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in ("record", "compare"):
        sys.exit(__doc__)
    if sys.argv[1] == "record":
        record(sys.argv[2])
    else:
        compare(sys.argv[2], Path(sys.argv[3] if len(sys.argv) > 3 else "golden-images"))
