#!/usr/bin/env python3
"""Hostile-input probe for the stsv command line.

Runs the stsv binary over several hundred hostile or edge inputs (scenes, meshes, textures,
light-sample dumps, command-line values, output paths, environment) and classifies each outcome:

  clean-error    exit 1 with a line "stsv: error: ..." that names what the case expects it to
  accepted       exit 0, and every check the probe knows for the case passed
  crash          killed by a signal, exit 2 ("internal error") or another status, or the text
                 of an uncaught exception (std::bad_alloc, "Could not convert", terminate called)
  hang           still running at the wall-clock limit (killed)
  unbounded      ran into the address-space cap (bad_alloc, VK_ERROR_OUT_OF_HOST_MEMORY, ...),
                 or exit 0 with a peak resident size above what the input justifies
  silent-wrong   exit 0 where the documentation says the input is refused, an input file
                 changed, an output written somewhere no option named or missing, or an output
                 whose content the probe knows to be wrong (an all-background image, a compare
                 that counts the wrong number of differences, a far-away scene that renders
                 differently from the same scene at the origin)
  false-refusal  exit 1 on an input the documentation says is valid
  unclear-error  non-zero exit without a "stsv: error:" line, or one that does not name the
                 option, file or key at fault, or prints raw control bytes
  questionable   exit 0 on an input the probe would rather see refused though the documentation
                 does not say so (duplicate JSON keys)

Python 3 standard library only. Every input is generated into a temporary folder; the case list
and its inputs are deterministic, so two runs over the same binary give the same table.

    python3 tests/probe/probe.py BUILD/cli/stsv --out probe.json [-j 2] [--only REGEX] [--keep DIR]
"""

from __future__ import annotations

import argparse
import ast
import base64
import copy
import hashlib
import json
import os
import re
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib
from array import array
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

KiB = 1 << 10
MiB = 1 << 20
GiB = 1 << 30

AS_CAP = 3 * GiB          # address-space cap of every run (prlimit --as)
MAX_MEMORY = "1G"         # --max-memory given to every render, compare, bench and info run
DEFAULT_TIMEOUT = 60.0    # seconds of wall clock a run may take
BUDGET_SMALL = 600        # MB of peak RSS an accepted run on a small input may use
BUDGET_LIMIT = 1024 + 256  # MB: the --max-memory limit plus the program's and lavapipe's own (~200 MB)
SIZE = ["--size", "32x24", "--samples", "16"]
W, H = 32, 24
BACKGROUND_SRGB = (39, 39, 48)  # linear (0.02, 0.02, 0.03), sRGB-encoded, 8 bits

CLASSES = ["clean-error", "accepted", "crash", "hang", "unbounded", "silent-wrong",
           "false-refusal", "unclear-error", "questionable", "probe-error"]
CLEAN = {"clean-error", "accepted"}


# ----------------------------------------------------------------------------------------------
# Input building blocks: JSON text with raw tokens, PNG, NumPy, glTF, special files

class Raw:
    """A JSON token written verbatim: NaN, 1e400, an integer no double holds."""

    def __init__(self, text: str):
        self.text = text


class Pairs:
    """A JSON object whose keys may repeat."""

    def __init__(self, items):
        self.items = list(items)


def jtext(v) -> str:
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, Pairs):
        return "{" + ", ".join(json.dumps(k) + ": " + jtext(x) for k, x in v.items) + "}"
    if isinstance(v, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + jtext(x) for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(jtext(x) for x in v) + "]"
    if isinstance(v, float):
        return repr(v)
    return json.dumps(v)


def png_chunk(kind: bytes, data: bytes, crc: int | None = None) -> bytes:
    c = zlib.crc32(kind + data) & 0xFFFFFFFF if crc is None else crc
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", c)


CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def png_bytes(w, h, pixels=None, color=6, depth=8, interlace=0, idat=None, pre=(), ihdr=None,
              filter_byte=0) -> bytes:
    if idat is None:
        stride = (w * CHANNELS[color] * depth + 7) // 8
        if pixels is None:
            pixels = bytes(stride * h)
        raw = b"".join(bytes([filter_byte]) + pixels[y * stride:(y + 1) * stride] for y in range(h))
        idat = zlib.compress(raw, 9)
    if ihdr is None:
        ihdr = struct.pack(">IIBBBBB", w, h, depth, color, 0, 0, interlace)
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + b"".join(pre) + png_chunk(b"IDAT", idat)
            + png_chunk(b"IEND", b""))


def zero_idat(w: int, h: int, channels: int, extra_rows: int = 0) -> bytes:
    """The zlib stream of an all-zero image, built a row at a time (a 16384² image never sits
    in memory)."""
    c = zlib.compressobj(9)
    row = bytes(1 + w * channels)
    parts = [c.compress(row) for _ in range(h + extra_rows)]
    parts.append(c.flush())
    return b"".join(parts)


def checker_rgba(n=16) -> bytes:
    """An n×n RGBA texture whose alpha is a 4-texel checker: half holes, half opaque."""
    px = bytearray()
    for y in range(n):
        for x in range(n):
            a = 255 if ((x // 4) + (y // 4)) % 2 == 0 else 0
            px += bytes([200, 200, 200, a])
    return png_bytes(n, n, bytes(px))


TEX = checker_rgba()


def read_png(path: Path):
    """(width, height, channels, pixel bytes) of an 8-bit non-interlaced PNG; pixels None for
    other formats."""
    data = path.read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, ihdr = 8, [], None
    while pos + 8 <= len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if ihdr is None:
        raise ValueError("no IHDR")
    w, h, depth, color, _, _, interlace = ihdr
    if depth != 8 or interlace or color not in (0, 2, 4, 6):
        return w, h, None, None
    ch = CHANNELS[color]
    raw = zlib.decompress(b"".join(idat))
    stride = w * ch
    out, prev = bytearray(), bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b = prev[i]
            c = prev[i - ch] if i >= ch else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        out += line
        prev = line
    return w, h, ch, bytes(out)


def npy_bytes(descr: str, shape, data: bytes | None = None, fortran=False, header: str | None = None,
              version=1) -> bytes:
    if header is None:
        header = "{'descr': %r, 'fortran_order': %s, 'shape': %s, }" % (
            descr, fortran, "(" + "".join("%d, " % s for s in shape).rstrip(" ") + ")"
            if len(shape) != 1 else "(%d,)" % shape[0])
    if data is None:
        n = 1
        for s in shape:
            n *= s
        itemsize = int(re.sub(r"\D", "", descr) or 1)
        data = bytes(n * itemsize)
    pre = 10 if version == 1 else 12
    pad = (64 - (pre + len(header) + 1) % 64) % 64
    h = (header + " " * pad + "\n").encode("latin1")
    size = struct.pack("<H", len(h)) if version == 1 else struct.pack("<I", len(h))
    return b"\x93NUMPY" + bytes([version, 0]) + size + h + data


def read_npy(path: Path):
    d = path.read_bytes()
    if d[:6] != b"\x93NUMPY":
        raise ValueError("not a .npy")
    if d[6] == 1:
        (hl,) = struct.unpack("<H", d[8:10])
        start = 10
    else:
        (hl,) = struct.unpack("<I", d[8:12])
        start = 12
    header = ast.literal_eval(d[start:start + hl].decode("latin1"))
    return header, d[start + hl:]


def read_vis(path: Path):
    header, data = read_npy(path)
    if header["descr"] != "<f4":
        raise ValueError("visibility dtype %s" % header["descr"])
    a = array("f")
    a.frombytes(data[:len(data) // 4 * 4])
    return header["shape"], a


class Fifo:
    pass


class Dir:
    pass


@dataclass
class Symlink:
    target: str


@dataclass
class Hardlink:
    source: str


@dataclass
class Mode:
    data: bytes
    mode: int


def materialize(root: Path, files: dict):
    for rel, v in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(v, Fifo):
            os.mkfifo(p)
        elif isinstance(v, Dir):
            p.mkdir(exist_ok=True)
        elif isinstance(v, Symlink):
            os.symlink(v.target, p)
        elif isinstance(v, Hardlink):
            os.link(root / v.source, p)
        elif isinstance(v, Mode):
            p.write_bytes(v.data)
            os.chmod(p, v.mode)
        elif isinstance(v, str):
            p.write_text(v)
        elif callable(v):
            p.write_bytes(v())
        else:
            p.write_bytes(v)


def snapshot(root: Path) -> dict:
    """relative path -> a fingerprint that never opens a FIFO or follows a link."""
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            p = Path(dirpath) / name
            rel = str(p.relative_to(root))
            st = os.lstat(p)
            if stat.S_ISREG(st.st_mode):
                h = hashlib.sha256()
                with open(p, "rb") as f:
                    for block in iter(lambda: f.read(1 << 20), b""):
                        h.update(block)
                out[rel] = "file:" + h.hexdigest()
            elif stat.S_ISLNK(st.st_mode):
                out[rel] = "link:" + os.readlink(p)
            elif stat.S_ISDIR(st.st_mode):
                out[rel] = "dir"
            else:
                out[rel] = "special:%o" % stat.S_IFMT(st.st_mode)
    return out


# ----------------------------------------------------------------------------------------------
# Cases

@dataclass
class Case:
    cid: str
    surface: str
    desc: str
    args: list
    files: dict = field(default_factory=dict)
    expect: str = "either"        # error | ok | either | refuse-preferred
    names: tuple = ()             # substrings a clean error must hold (case-insensitive)
    check: object = None          # callable(ctx) -> None or a problem, on exit 0
    env: dict = field(default_factory=dict)  # value None removes the variable
    budget_mb: int = BUDGET_SMALL
    timeout: float = DEFAULT_TIMEOUT
    limits: list = field(default_factory=list)  # extra prlimit options, e.g. ["--fsize=100"]
    max_memory: str | None = MAX_MEMORY
    outputs: object = "derive"    # "derive", None (do not check), or a list of allowed regexes
    required: tuple = ()          # outputs that must exist after exit 0


class Cases:
    def __init__(self):
        self.items: list[Case] = []
        self.ids: set[str] = set()

    def add(self, surface, name, args, **kw):
        cid = surface + "/" + name
        if cid in self.ids:
            raise SystemExit("duplicate case id " + cid)
        self.ids.add(cid)
        self.items.append(Case(cid, surface, kw.pop("desc", name), list(args), **kw))


def slug(s: str) -> str:
    return re.sub(r"[^A-Za-z0-9._+=-]+", "_", s)[:120] + "-" + hashlib.sha1(s.encode()).hexdigest()[:6]


def render(scene, *extra, backend="cpu", out="out.png"):
    a = ["render", scene, *SIZE, "--backend", backend]
    if out:
        a += ["-o", out]
    return a + list(extra)


# ----------------------------------------------------------------------------------------------
# Checks on accepted runs

def lit_is_background(png: Path) -> float:
    """Fraction of the lit image's pixels that hold the background colour."""
    w, h, ch, px = read_png(png)
    if px is None or ch < 3:
        return 0.0
    n = 0
    for i in range(0, len(px), ch):
        if all(abs(px[i + k] - BACKGROUND_SRGB[k]) <= 2 for k in range(3)):
            n += 1
    return n / (w * h)


def sees_scene(png="out.png", vis=None, shadow=True):
    """The lit image shows the scene (not all background) and, given a visibility file, it is
    finite, in [0, 1], of the frame's shape, and holds some shadow and some light."""

    def check(ctx):
        p = ctx.dir / png
        if not p.is_file():
            return "no %s written" % png
        bg = lit_is_background(p)
        if bg > 0.99:
            return "%s is all background (%.1f %% of the pixels)" % (png, 100 * bg)
        if vis:
            shape, v = read_vis(ctx.dir / vis)
            if list(shape) != [ctx.height, ctx.width]:
                return "%s has shape %s, not [%d, %d]" % (vis, shape, ctx.height, ctx.width)
            bad = [x for x in v if not (0.0 <= x <= 1.0)]
            if bad:
                return "%s holds %d values outside [0, 1] (e.g. %r)" % (vis, len(bad), bad[0])
            if shadow:
                dark = sum(1 for x in v if x < 0.5) / len(v)
                lit = sum(1 for x in v if x > 0.9) / len(v)
                if dark < 0.005:
                    return "%s holds no shadow (%.2f %% of pixels below 0.5)" % (vis, 100 * dark)
                if lit < 0.05:
                    return "%s is nearly all shadow (%.2f %% of pixels above 0.9)" % (vis, 100 * lit)
        return None

    return check


def vis_matches_aux(files, args, what, mean_tol=0.03, frac_tol=0.03, dark=False):
    """The visibility v.npy of the run equals that of a control run (files, args) within the
    tolerance; dark=True instead asks that the scene's surfaces are all in shadow."""

    def check(ctx):
        shape, v = read_vis(ctx.dir / "v.npy")
        if dark:
            w, h, ch, px = read_png(ctx.dir / "out.png")
            surf = [i for i in range(w * h)
                    if not all(abs(px[i * ch + k] - BACKGROUND_SRGB[k]) <= 2 for k in range(3))]
            lit = sum(1 for i in surf if v[i] > 0.05)
            if lit > 0.02 * max(1, len(surf)):
                return "%s: %d of %d surface pixels see the light (expected all in shadow)" % (
                    what, lit, len(surf))
            return None
        ref = ctx.aux(files, args)
        if ref is None:
            return "control run failed: " + " ".join(args)
        cshape, c = read_vis(ref / "v.npy")
        if list(cshape) != list(shape):
            return "shape %s, control %s" % (shape, cshape)
        d = [abs(a - b) for a, b in zip(v, c)]
        mean = sum(d) / len(d)
        frac = sum(1 for x in d if x > 0.25) / len(d)
        if mean > mean_tol or frac > frac_tol:
            return "%s: visibility differs from the control (%s): mean |dv| %.3f, %.1f %% of pixels off by > 0.25" % (
                what, " ".join(args[1:2] + args[-4:]), mean, 100 * frac)
        return None

    return check


def stdout_has(pattern, what):
    def check(ctx):
        if not re.search(pattern, ctx.stdout, re.M):
            m = ctx.stdout.strip().splitlines()
            return "%s (stdout: %s)" % (what, " | ".join(m[:4]))
        return None

    return check


def all_checks(*checks):
    def check(ctx):
        for c in checks:
            if c:
                r = c(ctx)
                if r:
                    return r
        return None

    return check


# ----------------------------------------------------------------------------------------------
# Outputs a command names: the files exit 0 may create in the case's folder

OUTPUT_OPTIONS = {
    "render": ["-o", "--visibility", "--dump-ls", "--shadow-map", "--stats"],
    "compare": ["--out", "--report", "--json", "--sheet"],
    "bench": ["--json"],
    "info": [],
}


def option_values(args, name):
    vals = []
    for i, a in enumerate(args):
        if a == name and i + 1 < len(args):
            vals.append(args[i + 1])
        elif a.startswith(name + "="):
            vals.append(a[len(name) + 1:])
    return vals


def derive_outputs(args):
    """(allowed path regexes, required paths), relative to the case folder."""
    cmd = args[0] if args else ""
    allowed, required = [], []

    def rel(p):
        return os.path.normpath(p)

    if cmd == "render":
        given = {o: option_values(args, o) for o in OUTPUT_OPTIONS["render"]}
        if not (given["-o"] or given["--visibility"] or given["--dump-ls"] or given["--stats"]):
            scene = args[1] if len(args) > 1 else ""
            given["-o"] = [Path(scene).stem + ".png"]
        for opt, vals in given.items():
            for v in vals:
                if not v:
                    continue
                p = rel(v)
                required.append(p)
                allowed.append(re.escape(p))
                allowed.append(re.escape(p) + r"\.json")
                if opt in ("--dump-ls", "--shadow-map"):
                    stem, ext = os.path.splitext(p)
                    allowed.append(re.escape(stem) + r"_light\d+" + re.escape(ext) + r"(\.json)?")
    elif cmd == "compare":
        for opt in ("--out", "--report"):
            for v in option_values(args, opt):
                if v:
                    allowed.append(re.escape(rel(v)) + r"(/.*)?")
        for opt in ("--json", "--sheet"):
            for v in option_values(args, opt):
                if v:
                    required.append(rel(v))
                    allowed.append(re.escape(rel(v)))
    elif cmd == "bench":
        for v in option_values(args, "--json"):
            if v:
                required.append(rel(v))
                allowed.append(re.escape(rel(v)))
    return allowed, required


# ----------------------------------------------------------------------------------------------
# Running one case

CRASH_MARKERS = ["internal error", "terminate called", "what():", "Could not convert", "std::",
                 "basic_string", "vector::", "Assertion", "AddressSanitizer", "runtime error:",
                 "Segmentation fault", "stack smashing", "double free", "corrupted", "malloc():",
                 "free():", "Aborted", "core dumped"]
MEM_MARKERS = ["bad_alloc", "Cannot allocate memory", "out of memory", "Out of memory",
               "OUT_OF_HOST_MEMORY", "OUT_OF_DEVICE_MEMORY", "std::length_error", "mmap failed"]
ERROR_LINE = re.compile(r"^stsv: error: ")


@dataclass
class Result:
    case: Case
    klass: str = ""
    detail: str = ""
    rc: int | None = None
    signal: str | None = None
    timed_out: bool = False
    wall_s: float = 0.0
    maxrss_mb: float = 0.0
    stderr: str = ""
    stdout: str = ""
    command: str = ""
    left_files: list = field(default_factory=list)


LAUNCHER = r"""
import os, signal, sys
report, argv = sys.argv[1], sys.argv[2:]
pid = os.fork()
if pid == 0:
    # A shell starts programs with SIGPIPE and SIGXFSZ at their defaults; Python ignores both.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    signal.signal(signal.SIGXFSZ, signal.SIG_DFL)
    try:
        os.execvp(argv[0], argv)
    except OSError as e:
        os.write(2, ("probe: cannot run %s: %s\n" % (argv[0], e)).encode())
        os._exit(127)
_, status, ru = os.wait4(pid, 0)
with open(report, "w") as f:
    f.write("%d %d\n" % (status, ru.ru_maxrss))
"""


class Probe:
    def __init__(self, stsv: Path, work: Path, use_prlimit: bool):
        self.stsv = stsv
        self.work = work
        self.use_prlimit = use_prlimit
        self.aux_lock = threading.Lock()
        self.aux_cache: dict[str, Path | None] = {}
        (work / "cases").mkdir(parents=True, exist_ok=True)
        (work / "logs").mkdir(exist_ok=True)
        (work / "aux").mkdir(exist_ok=True)
        (work / "cache").mkdir(exist_ok=True)

    def env_for(self, case_env: dict, d: Path) -> dict:
        """The run's environment: ours, the converged-reference cache inside the work folder,
        and the case's variables ($CASE is the case's folder)."""
        env = dict(os.environ)
        env["STSV_CACHE_DIR"] = str(self.work / "cache")
        for k, v in case_env.items():
            if v is None:
                env.pop(k, None)
            else:
                env[k] = v.replace("$CASE", str(d))
        return env

    def argv(self, case: Case) -> list:
        args = list(case.args)
        if (case.max_memory and args and args[0] in ("render", "compare", "bench", "info")
                and not any(a == "--max-memory" or a.startswith("--max-memory=") for a in args)):
            args += ["--max-memory", case.max_memory]
        return args

    def spawn(self, argv, cwd: Path, env: dict, timeout: float, limits, log: Path):
        """Runs argv under the caps; (status, peak RSS in KiB, timed out, wall seconds).

        The binary is started by a small Python launcher that forks it and reports its wait
        status and peak RSS: a child forked from this process would count the probe's own
        pages in its ru_maxrss (the high-water mark survives exec)."""
        full = [str(self.stsv)] + argv
        if self.use_prlimit:
            full = ["prlimit", "--as=%d" % AS_CAP, "--core=0", *limits, "--"] + full
        report = Path(str(log) + ".rusage")
        if report.exists():
            report.unlink()
        full = [sys.executable, "-S", "-c", LAUNCHER, str(report)] + full
        out = open(str(log) + ".out", "wb")
        err = open(str(log) + ".err", "wb")
        preexec = None
        if not self.use_prlimit:
            import resource

            def preexec():
                resource.setrlimit(resource.RLIMIT_AS, (AS_CAP, AS_CAP))
                resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

        t0 = time.monotonic()
        p = subprocess.Popen(full, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                             start_new_session=True, preexec_fn=preexec)
        fired = threading.Event()

        def kill():
            fired.set()
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass

        timer = threading.Timer(timeout, kill)
        timer.start()
        try:
            _, lstatus, _ = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        wall = time.monotonic() - t0
        p.returncode = 0  # reaped above; keeps Popen from waiting again
        out.close()
        err.close()
        try:
            status, maxrss = (int(x) for x in report.read_text().split())
        except (OSError, ValueError):
            status, maxrss = lstatus, 0  # the launcher was killed (timeout) or failed
        return status, maxrss, fired.is_set(), wall

    def aux(self, files: dict, args: list):
        """A control run, once per (files, args): its folder, or None when it failed."""
        key = hashlib.sha1((jtext(sorted((k, repr(v) if not isinstance(v, (bytes, str)) else
                                          hashlib.sha1(v if isinstance(v, bytes) else v.encode()).hexdigest())
                                         for k, v in files.items())) + "\0" + "\0".join(args)).encode()).hexdigest()[:16]
        with self.aux_lock:
            if key in self.aux_cache:
                return self.aux_cache[key]
            d = self.work / "aux" / key
            d.mkdir(parents=True, exist_ok=True)
            materialize(d, files)
            argv = args + ["--max-memory", MAX_MEMORY]
            status, _, timed_out, wall = self.spawn(argv, d, self.env_for({}, d), DEFAULT_TIMEOUT, [],
                                                     self.work / "logs" / ("aux-" + key))
            ok = not timed_out and os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0
            self.aux_cache[key] = d if ok else None
            return self.aux_cache[key]

    def run(self, case: Case) -> Result:
        d = self.work / "cases" / slug(case.cid)
        if d.exists():
            shutil.rmtree(d)
        d.mkdir(parents=True)
        materialize(d, case.files)
        before = snapshot(d)
        argv = self.argv(case)
        env = self.env_for(case.env, d)
        log = self.work / "logs" / slug(case.cid)
        status, maxrss, timed_out, wall = self.spawn(argv, d, env, case.timeout, case.limits, log)
        r = Result(case)
        r.timed_out = timed_out
        r.wall_s = round(wall, 2)
        r.maxrss_mb = round(maxrss / 1024.0, 1)
        r.stderr = Path(str(log) + ".err").read_bytes().decode("utf-8", "backslashreplace")
        r.stdout = Path(str(log) + ".out").read_bytes().decode("utf-8", "backslashreplace")
        envs = " ".join("%s=%s" % (k, shquote(v if v is not None else "")) for k, v in case.env.items())
        r.command = "cd $W/cases/%s && %s%s %s" % (slug(case.cid), envs + " " if envs else "",
                                                    "stsv", " ".join(shquote(a) for a in argv))
        if case.limits:
            r.command = r.command.replace("&& ", "&& prlimit %s -- " % " ".join(case.limits), 1)
        if os.WIFSIGNALED(status):
            r.signal = signal.Signals(os.WTERMSIG(status)).name
        else:
            r.rc = os.WEXITSTATUS(status)
        after = snapshot(d)
        self.classify(r, d, before, after, argv)
        return r

    def classify(self, r: Result, d: Path, before: dict, after: dict, argv: list):
        case = r.case
        err = r.stderr
        lines = [ln for ln in err.splitlines() if ln.strip()]
        mem_hit = [m for m in MEM_MARKERS if m in err]
        if mem_hit and all(m.startswith("OUT_OF_") for m in mem_hit) and r.maxrss_mb < 1024:
            mem_hit = []  # a Vulkan result the loader also returns for a bad manifest, far below the cap
        crash_hit = [m for m in CRASH_MARKERS if m in err]
        if case.outputs == "derive":
            allowed, required = derive_outputs(argv)
        elif case.outputs is None:
            allowed, required = None, []
        else:
            allowed, required = list(case.outputs), []
        required = list(required) + list(case.required)
        allowed_re = re.compile("^(" + "|".join(allowed) + ")$") if allowed else None
        new = sorted(k for k in after if k not in before and after[k] != "dir")
        changed = sorted(k for k in before if k in after and before[k] != after[k]
                         and not (allowed_re and allowed_re.match(k)))
        vanished = sorted(k for k in before if k not in after)
        input_problem = ""
        if changed or vanished:
            input_problem = "input changed: " + ", ".join(changed + ["%s (removed)" % v for v in vanished])

        def first_error():
            for ln in lines:
                if ERROR_LINE.match(ln):
                    return ln
            return lines[0] if lines else ""

        if r.timed_out:
            r.klass, r.detail = "hang", "killed after %.0f s" % case.timeout
        elif mem_hit:
            r.klass, r.detail = "unbounded", "hit the %d GiB address-space cap (%s)" % (AS_CAP // GiB, mem_hit[0])
        elif r.signal:
            r.klass, r.detail = "crash", "killed by " + r.signal
        elif r.rc == 2 or crash_hit:
            r.klass = "crash"
            if r.rc == 2:
                r.detail = "exit 2: internal error"
            else:
                r.detail = "exit %s with an exception's own text on stderr (%r)" % (r.rc, crash_hit[0])
        elif r.rc not in (0, 1):
            r.klass, r.detail = "crash", "unexpected exit status %s" % r.rc
        elif r.rc == 1:
            line = first_error()
            ctrl = [c for c in err if ord(c) < 32 and c not in "\n\t"]
            missing = [n for n in case.names if n.lower() not in err.lower()]
            if not ERROR_LINE.match(line):
                r.klass, r.detail = "unclear-error", "exit 1 without a 'stsv: error:' line"
            elif ctrl:
                r.klass, r.detail = "unclear-error", "raw control byte %r on stderr" % ctrl[0]
            elif case.expect == "ok":
                r.klass, r.detail = "false-refusal", "the documentation says this input is valid"
            elif missing:
                r.klass, r.detail = "unclear-error", "the error does not name " + ", ".join(repr(m) for m in missing)
            else:
                r.klass = "clean-error"
            if input_problem:
                r.klass, r.detail = "silent-wrong", input_problem + " (the run failed)"
            left = [k for k in new]
            if left:
                r.left_files = left
        else:  # exit 0
            problems = []
            if input_problem:
                problems.append(input_problem)
            if allowed_re is not None or case.outputs == "derive":
                stray = [k for k in new if not (allowed_re and allowed_re.match(k))]
                if stray:
                    problems.append("wrote files no option named: " + ", ".join(stray[:5]))
            for q in required:
                p = d / q
                if not q.startswith("..") and not os.path.isabs(q):
                    if not p.is_file() and not (p.is_symlink()):
                        problems.append("named output %s not written" % q)
                    elif p.is_file() and p.stat().st_size == 0:
                        problems.append("named output %s is empty" % q)
            if case.expect == "error":
                problems.insert(0, "accepted an input the documentation says is refused")
            if not problems and case.check:
                ctx = Ctx(self, d, r, argv)
                try:
                    msg = case.check(ctx)
                except Exception as e:  # a check that cannot read the output is a finding too
                    msg = "output unreadable: %s: %s" % (type(e).__name__, e)
                if msg:
                    problems.append(msg)
            if not problems and argv and argv[0] == "render":
                msg = check_render_png(d, argv)
                if msg:
                    problems.append(msg)
            if r.maxrss_mb > case.budget_mb:
                r.klass = "unbounded"
                r.detail = "exit 0 with a peak of %.0f MB (budget %d MB)" % (r.maxrss_mb, case.budget_mb)
                if problems:
                    r.detail += "; " + "; ".join(problems)
            elif problems:
                r.klass, r.detail = "silent-wrong", "; ".join(problems)
            elif case.expect == "refuse-preferred":
                r.klass, r.detail = "questionable", "accepted; a refusal would be safer"
            else:
                r.klass = "accepted"


def check_render_png(d: Path, argv) -> str | None:
    """Every PNG output of a render has the frame's size."""
    size = option_values(argv, "--size")
    if not size:
        return None
    m = re.fullmatch(r"(\d+)x(\d+)", size[-1])
    if not m:
        return None
    w, h = int(m.group(1)), int(m.group(2))
    outs = option_values(argv, "-o") + option_values(argv, "--visibility")
    if not option_values(argv, "-o") and not option_values(argv, "--visibility") and \
            not option_values(argv, "--dump-ls") and not option_values(argv, "--stats"):
        outs = [Path(argv[1]).stem + ".png"]
    for o in outs:
        p = d / o
        if o.lower().endswith(".png") and p.is_file():
            try:
                pw, ph, _, _ = read_png(p)
            except Exception as e:
                return "%s is not a readable PNG (%s)" % (o, e)
            if (pw, ph) != (w, h):
                return "%s is %dx%d, not the --size %dx%d" % (o, pw, ph, w, h)
    return None


class Ctx:
    def __init__(self, probe: Probe, d: Path, r: Result, argv):
        self.probe = probe
        self.dir = d
        self.stdout = r.stdout
        self.stderr = r.stderr
        self.argv = argv
        size = option_values(argv, "--size")
        m = re.fullmatch(r"(\d+)x(\d+)", size[-1]) if size else None
        self.width, self.height = (int(m.group(1)), int(m.group(2))) if m else (W, H)

    def aux(self, files, args):
        return self.probe.aux(files, args)


def shquote(s: str) -> str:
    if s and re.fullmatch(r"[A-Za-z0-9_./=:,+%@-]+", s):
        return s
    return "'" + s.replace("'", "'\\''") + "'"


# ----------------------------------------------------------------------------------------------
# The probe's scene: a floor, a 1 m opaque square 1 m above it whose shadow falls beside it, a
# perforated quad, one square light; the camera sees floor, occluder and shadow.

def quad_y(cx, cy, cz, half, off):
    """Vertices of a horizontal square facing +y, and its two counter-clockwise triangles."""
    ox, oy, oz = off
    v = [[cx - half + ox, cy + oy, cz - half + oz], [cx + half + ox, cy + oy, cz - half + oz],
         [cx + half + ox, cy + oy, cz + half + oz], [cx - half + ox, cy + oy, cz + half + oz]]
    return v, [[0, 3, 2], [0, 2, 1]]


def scene_dict(off=(0.0, 0.0, 0.0), floor_half=100.0, ceiling=None, light=None, lights=None):
    ox, oy, oz = off
    fv, ft = quad_y(0, 0, 0, floor_half, off)
    qv, qt = quad_y(0, 1, 0, 0.5, off)
    meshes = [
        {"name": "floor", "material": "floor", "vertices": fv, "triangles": ft},
        {"name": "occluder", "material": "occluder", "vertices": qv, "triangles": qt,
         "texcoords": [[0, 0], [1, 0], [1, 1], [0, 1]]},
        {"name": "grate", "material": "grate", "quad": {"size": [1, 1], "uvRepeat": [2, 2]},
         "transform": {"scale": 1, "rotate": {"axis": [0, 1, 0], "degrees": 30},
                       "translate": [-1.5 + ox, 0.6 + oy, 1.5 + oz]}},
    ]
    materials = [
        {"name": "floor", "albedo": 0.7},
        {"name": "occluder", "albedo": [0.5, 0.5, 0.5], "doubleSided": True},
        {"name": "grate", "albedo": 0.6, "alphaTexture": "tex.png", "alphaChannel": "auto",
         "alphaMode": "mask", "alphaFactor": 1, "alphaCutoff": 0.5, "wrap": "repeat",
         "doubleSided": True},
    ]
    if ceiling is not None:
        y, facing, double = ceiling
        cv, ct = quad_y(0, y, 0, floor_half, off)
        if facing == "down":
            ct = [[0, 2, 3], [0, 1, 2]]
        meshes.append({"name": "ceiling", "material": "ceiling", "vertices": cv, "triangles": ct})
        materials.append({"name": "ceiling", "albedo": 0.7, "doubleSided": double})
    if lights is None:
        lights = [light or {"type": "rectangle", "position": [-2 + ox, 3 + oy, 0 + oz], "normal": [0, -1, 0],
                            "size": [0.5, 0.5], "tangent": [1, 0, 0], "radiance": [40, 40, 40]}]
    return {
        "description": "stsv probe scene",
        "camera": {"eye": [0.5 + ox, 2.5 + oy, 5 + oz], "target": [0.5 + ox, 0 + oy, 0 + oz],
                   "up": [0, 1, 0], "fovY": 50},
        "materials": materials,
        "meshes": meshes,
        "lights": lights,
    }


def scene_files(d=None, **kw):
    return {"scene.json": jtext(d if d is not None else scene_dict(**kw)), "tex.png": TEX}


def set_path(d, path, value):
    d = copy.deepcopy(d)
    cur = d
    for k in path[:-1]:
        cur = cur[k]
    cur[path[-1]] = value
    return d


def del_path(d, path):
    d = copy.deepcopy(d)
    cur = d
    for k in path[:-1]:
        cur = cur[k]
    del cur[path[-1]]
    return d


def last_name(path):
    for k in reversed(path):
        if isinstance(k, str):
            return k
    return ""


WRONG_TYPES = [("string", "x"), ("null", None), ("true", True), ("object", {})]
NONFINITE = [("NaN", Raw("NaN")), ("Infinity", Raw("Infinity")), ("-Infinity", Raw("-Infinity")),
             ("1e400", Raw("1e400")), ("-1e400", Raw("-1e400"))]
EXTREMES = [("1e38", 1e38), ("-1e38", -1e38), ("1e-38", 1e-38), ("-0", -0.0), ("0", 0), ("-1", -1),
            ("0.5", 0.5), ("2", 2), ("1e308", 1e308), ("2^64", Raw("18446744073709551616"))]
FLOAT_MAX = 3.4028234663852886e38


def in_range(v, rng):
    """'ok' inside the documented range, 'error' outside, 'either' without one."""
    if rng is None:
        return "refuse-preferred" if abs(v) > FLOAT_MAX else "either"
    lo, hi, lo_open, hi_open = rng
    if v < lo or v > hi or (lo_open and v == lo) or (hi_open and v == hi):
        return "error"
    return "either"


def number_of(v):
    if isinstance(v, Raw):
        try:
            return float(v.text)
        except ValueError:
            return None
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    return float(v)


UNIT = (0.0, 1.0, False, False)
POSITIVE = (0.0, float("inf"), True, False)


def json_surface(c: Cases):
    base = scene_dict()
    files_of = lambda d: scene_files(d)  # noqa: E731
    args = render("scene.json", "--visibility", "v.npy")
    ok_check = sees_scene(vis="v.npy", shadow=True)
    soft_check = sees_scene()

    c.add("json", "base", args, files=files_of(base), expect="ok", check=ok_check,
          desc="the probe scene itself (control)")

    M, F, O, G, L = ("materials", 2), ("meshes", 0), ("meshes", 1), ("meshes", 2), ("lights", 0)
    numbers = [
        (M + ("albedo",), UNIT), (M + ("alphaFactor",), UNIT), (M + ("alphaCutoff",), UNIT),
        (F + ("vertices", 0, 0), None), (F + ("triangles", 0, 0), "index"),
        (O + ("texcoords", 0, 0), None), (G + ("quad", "size", 0), None),
        (G + ("quad", "uvRepeat", 0), None), (G + ("transform", "scale"), POSITIVE),
        (G + ("transform", "rotate", "degrees"), None), (G + ("transform", "translate", 0), None),
        (L + ("position", 0), None), (L + ("size", 0), POSITIVE), (L + ("radiance", 0), None),
        (("camera", "eye", 0), None), (("camera", "fovY"), (0.0, 180.0, True, True)),
        (("materials", 0, "albedo"), UNIT),
    ]
    for path, rng in numbers:
        pname = ".".join(str(k) for k in path)
        for label, v in WRONG_TYPES:
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect="error", names=("scene.json", last_name(path)))
        for label, v in NONFINITE:
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect="error", names=("scene.json",))
        for label, v in EXTREMES:
            x = number_of(v)
            if rng == "index":
                exp = "error" if x not in (0.0, 1.0, 2.0, 3.0) else "either"
            else:
                exp = in_range(x, rng)
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect=exp, names=("scene.json", last_name(path)) if exp == "error" else (),
                  check=soft_check if not path[0] == "camera" else None)
    for label, v in [("4294967296", 4294967296), ("4", 4), ("1.5", 1.5), ("string-0", "0")]:
        c.add("json", "triangle-index=%s" % label, args,
              files=files_of(set_path(base, F + ("triangles", 0, 0), v)), expect="error",
              names=("scene.json", "triangles"))

    vectors = [
        (L + ("normal",), "nonzero"), (L + ("tangent",), None), (L + ("size",), None),
        (L + ("radiance",), None), (("camera", "up"), "nonzero"), (("camera", "target"), None),
        (G + ("transform", "rotate", "axis"), "nonzero"), (G + ("transform", "translate"), None),
        (G + ("quad", "size"), None), (F + ("vertices", 0), None), (O + ("texcoords", 0), None),
        (M + ("albedo",), None),
    ]
    vec_values = [
        ("empty", [], "error"), ("one", [1], "error"), ("four", [1, 2, 3, 4], "error"),
        ("strings", ["a", "b", "c"], "error"), ("nested", [[1, 2, 3]], "error"),
        ("zero", [0, 0, 0], None), ("huge", [1e38, 1e38, 1e38], "either"),
        ("nan", [Raw("NaN"), 0, 0], "error"), ("object", {"x": 1}, "error"), ("string", "1,2,3", "error"),
        ("long", list(range(100000)), "error"),
    ]
    for path, rule in vectors:
        pname = ".".join(str(k) for k in path)
        for label, v, exp in vec_values:
            if exp is None:
                exp = "error" if rule == "nonzero" else "either"
            if label == "huge" and path[-1] == "albedo":
                exp = "error"
            c.add("json", "%s=vec-%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect=exp, names=("scene.json", last_name(path)) if exp == "error" else (),
                  check=soft_check if path[0] != "camera" else None)

    enums = [(M + ("alphaChannel",), "alpha"), (M + ("alphaMode",), "blend"), (M + ("wrap",), "clamp"),
             (L + ("type",), "disk")]
    for path, good in enums:
        pname = ".".join(str(k) for k in path)
        for label, v, exp in [("empty", "", "error"), ("bogus", "bogus", "error"),
                              ("upper", good.upper(), "either"), ("space", good + " ", "error"),
                              ("number", 5, "error"), ("null", None, "error")]:
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect=exp, names=("scene.json", last_name(path)) if exp == "error" else ())
    for label, v in [("string", "true"), ("one", 1), ("null", None), ("zero", 0)]:
        c.add("json", "doubleSided=%s" % label, args,
              files=files_of(set_path(base, M + ("doubleSided",), v)), expect="error",
              names=("scene.json", "doubleSided"))
    for path in [M + ("name",), G + ("material",), G + ("name",), ("description",)]:
        pname = ".".join(str(k) for k in path)
        for label, v, exp in [("number", 5, "error"), ("null", None, "error"), ("array", ["a"], "error"),
                              ("long", "n" * 100000, "either"), ("nul", "a\u0000b", "either"),
                              ("escape", "\u001b[31mred", "either"), ("empty", "", "either")]:
            if path[-1] in ("name", "material") and path[0] == "materials" and label in ("long", "nul", "escape", "empty"):
                exp = "error"  # the meshes name "grate": renaming the material leaves them without one
            if path[-1] == "material" and label in ("long", "nul", "escape", "empty"):
                exp = "error"
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect=exp, names=("scene.json",) if exp == "error" else ())
    for path in [F + ("vertices",), F + ("triangles",), O + ("texcoords",), ("meshes",), ("lights",),
                 ("materials",)]:
        pname = ".".join(str(k) for k in path)
        for label, v in [("empty", []), ("object", {}), ("null", None), ("string", "x")]:
            exp = "error"
            if path == ("materials",) and label == "empty":
                exp = "error"  # meshes name materials that are then missing
            c.add("json", "%s=%s" % (pname, label), args, files=files_of(set_path(base, path, v)),
                  expect=exp, names=("scene.json",))

    # Structure of the file.
    text = jtext(base)
    struct_cases = [
        ("empty-file", "", "error"), ("whitespace", "  \n ", "error"), ("null", "null", "error"),
        ("array", "[]", "error"), ("number", "42", "error"), ("string", '"scene"', "error"),
        ("empty-object", "{}", "error"), ("truncated-half", text[: len(text) // 2], "error"),
        ("truncated-last-brace", text[:-1], "error"), ("trailing-comma", text[:-1] + ", }", "error"),
        ("trailing-garbage", text + " x", "error"), ("two-documents", text + text, "error"),
        ("bom", "\ufeff" + text, "either"), ("comments", "// c\n/* d */" + text, "ok"),
        ("unterminated-comment", "/* " + text, "error"), ("nul-byte", text[:20] + "\0" + text[20:], "error"),
        ("invalid-utf8", None, "either"),
        ("unknown-top-key", text[:-1] + ', "bogus": 1}', "error"),
        ("unknown-light-key", jtext(set_path(base, L + ("bogus",), 1)), "error"),
        ("lone-surrogate", jtext(set_path(base, ("description",), Raw('"\\ud800"'))), "either"),
    ]
    for name, t, exp in struct_cases:
        if t is None:
            data = text.replace("stsv probe scene", "stsv \xff\xfe scene").encode("latin1")
        else:
            data = t.encode("utf-8")
        c.add("json", "file-" + name, args, files={"scene.json": data, "tex.png": TEX}, expect=exp,
              names=("scene.json",) if exp == "error" else (), check=ok_check if exp == "ok" else None)
    # Duplicate keys: one value is silently dropped.
    dup_top = Pairs(list(base.items()) + [("lights", [])])
    c.add("json", "duplicate-top-lights", args, files=files_of(dup_top), expect="refuse-preferred")
    light = base["lights"][0]
    dup_light = set_path(base, ("lights",), [Pairs(list(light.items()) + [("position", [100, 100, 100])])])
    c.add("json", "duplicate-light-position", args, files=files_of(dup_light), expect="refuse-preferred")
    mat = base["materials"][2]
    dup_mat = set_path(base, ("materials", 2), Pairs(list(mat.items()) + [("albedo", 0.1)]))
    c.add("json", "duplicate-material-albedo", args, files=files_of(dup_mat), expect="refuse-preferred")
    dup_name = set_path(base, ("materials",), base["materials"] + [{"name": "floor", "albedo": 0.1}])
    c.add("json", "duplicate-material-name", args, files=files_of(dup_name), expect="error",
          names=("scene.json", "floor"))
    # Deep nesting.
    for n in (1000, 100000, 1000000):
        c.add("json", "deep-array-%d" % n, args,
              files=files_of(set_path(base, ("description",), Raw("[" * n + "]" * n))), expect="error",
              names=("scene.json",))
        c.add("json", "deep-object-%d" % n, args,
              files=files_of(set_path(base, ("camera",), Raw('{"a":' * n + "1" + "}" * n))), expect="error",
              names=("scene.json",))
    rot_list = [{"axis": [0, 1, 0], "degrees": 1}] * 100000
    c.add("json", "rotate-list-100000", args,
          files={"scene.json": lambda: jtext(set_path(base, G + ("transform", "rotate"), rot_list)).encode(), "tex.png": TEX},
          check=soft_check)
    c.add("json", "euler-and-rotate", args,
          files=files_of(set_path(base, G + ("transform", "euler"), [10, 20, 30])), expect="either")
    c.add("json", "euler-nan", args,
          files=files_of(set_path(del_path(base, G + ("transform", "rotate")), G + ("transform", "euler"),
                                  [Raw("NaN"), 0, 0])), expect="error", names=("scene.json",))
    # Huge counts.
    def many_vertices():
        v = [[i * 1e-3, 0.0, 0.0] for i in range(1000000)]
        v[:4] = base["meshes"][0]["vertices"]
        return jtext(set_path(base, F + ("vertices",), v)).encode()

    c.add("json", "vertices-1e6", args, files={"scene.json": many_vertices, "tex.png": TEX},
          check=soft_check, budget_mb=BUDGET_LIMIT)
    c.add("json", "triangles-1e6-copies", args,
          files={"scene.json": lambda: jtext(set_path(base, F + ("triangles",), [[0, 3, 2]] * 1000000)).encode(),
                 "tex.png": TEX}, budget_mb=BUDGET_LIMIT,
          desc="a million copies of one triangle: 2.6 GB at 2.6 KB a triangle, above --max-memory 1G")
    c.add("json", "materials-100000", args,
          files={"scene.json": lambda: jtext(set_path(base, ("materials",), base["materials"] +
                                                      [{"name": "m%d" % i} for i in range(100000)])).encode(),
                 "tex.png": TEX}, check=soft_check)
    c.add("json", "quads-20000", args,
          files={"scene.json": lambda: jtext(set_path(base, ("meshes",), base["meshes"] + [
              {"material": "occluder", "quad": {"size": [0.01, 0.01]},
               "transform": {"translate": [-3 + (i % 100) * 0.02, 0.5 + (i // 100) * 0.01, -2]}}
              for i in range(20000)])).encode(), "tex.png": TEX}, budget_mb=BUDGET_LIMIT, check=soft_check)
    lights = [dict(base["lights"][0], radiance=[0.1, 0.1, 0.1]) for _ in range(300)]
    c.add("json", "lights-300", args, files=files_of(set_path(base, ("lights",), lights)), check=soft_check,
          timeout=120, budget_mb=BUDGET_LIMIT)
    # References and sources.
    c.add("json", "material-unknown", args, files=files_of(set_path(base, G + ("material",), "nope")),
          expect="error", names=("scene.json", "nope"))
    c.add("json", "mesh-two-sources", args,
          files=files_of(set_path(base, G + ("vertices",), base["meshes"][1]["vertices"])), expect="error",
          names=("scene.json",))
    c.add("json", "mesh-no-source", args, files=files_of(del_path(base, G + ("quad",))), expect="error",
          names=("scene.json",))
    c.add("json", "texcoords-short", args,
          files=files_of(set_path(base, O + ("texcoords",), [[0, 0]])), expect="error", names=("scene.json",))
    c.add("json", "triangle-two-indices", args,
          files=files_of(set_path(base, F + ("triangles", 0), [0, 1])), expect="error", names=("scene.json",))
    c.add("json", "degenerate-occluder", args,
          files=files_of(set_path(base, O + ("triangles",), [[0, 0, 1], [2, 2, 2]])), check=soft_check,
          desc="faces with a repeated vertex are skipped and counted")
    c.add("json", "all-degenerate", args,
          files=files_of(set_path(base, ("meshes",), [{"name": "d", "material": "floor",
                                                      "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]],
                                                      "triangles": [[0, 1, 2]]}])), expect="error",
          names=("scene.json",), desc="collinear vertices only: no triangle with area")
    c.add("json", "no-camera", args, files=files_of(del_path(base, ("camera",))), check=soft_check,
          desc="the bounding box is framed")
    c.add("json", "camera-eye-is-target", args,
          files=files_of(set_path(base, ("camera", "target"), base["camera"]["eye"])), expect="error",
          names=("scene.json", "camera"))
    c.add("json", "camera-up-along-view", args,
          files=files_of(set_path(base, ("camera", "up"), [0, -2.5, -5])), expect="error",
          names=("scene.json", "up"))
    for name, lt in [("directional-90", {"type": "directional", "direction": [0, 1, 0], "angularRadius": 90, "radiance": 5}),
                     ("directional-89.99", {"type": "directional", "direction": [0, 1, 0], "angularRadius": 89.99, "radiance": 5}),
                     ("directional-0", {"type": "directional", "direction": [0, 1, 0], "angularRadius": 0, "radiance": 5}),
                     ("directional-zero-dir", {"type": "directional", "direction": [0, 0, 0], "angularRadius": 1, "radiance": 5}),
                     ("disk-radius-0", {"type": "disk", "position": [-2, 3, 0], "normal": [0, -1, 0], "radius": 0, "radiance": 40}),
                     ("disk-radius-1e38", {"type": "disk", "position": [-2, 3, 0], "normal": [0, -1, 0], "radius": 1e38, "radiance": 40}),
                     ("sphere-radius-neg", {"type": "sphere", "position": [-2, 3, 0], "radius": -1, "radiance": 40}),
                     ("sphere-through-floor", {"type": "sphere", "position": [-2, 0, 0], "radius": 0.5, "radiance": 40}),
                     ("sphere-at-eye", {"type": "sphere", "position": [0.5, 2.5, 5], "radius": 0.1, "radiance": 40}),
                     ("rect-axes-parallel", {"type": "rectangle", "position": [-2, 3, 0], "axisU": [1, 0, 0], "axisV": [2, 0, 0], "radiance": 40}),
                     ("rect-axes-zero", {"type": "rectangle", "position": [-2, 3, 0], "axisU": [0, 0, 0], "axisV": [0, 0, 1], "radiance": 40}),
                     ("rect-axes-and-size", {"type": "rectangle", "position": [-2, 3, 0], "axisU": [1, 0, 0], "axisV": [0, 0, 1], "size": 1, "normal": [0, -1, 0], "radiance": 40}),
                     ("rect-tangent-along-normal", {"type": "rectangle", "position": [-2, 3, 0], "normal": [0, -1, 0], "tangent": [0, 1, 0], "size": 0.5, "radiance": 40}),
                     ("rect-radiance-negative", {"type": "rectangle", "position": [-2, 3, 0], "normal": [0, -1, 0], "size": 0.5, "radiance": -40}),
                     ("rect-radiance-1e38", {"type": "rectangle", "position": [-2, 3, 0], "normal": [0, -1, 0], "size": 0.5, "radiance": 1e38}),
                     ("rect-inside-occluder", {"type": "rectangle", "position": [0, 1, 0], "normal": [0, -1, 0], "size": 0.2, "radiance": 40}),
                     ("rect-below-floor", {"type": "rectangle", "position": [0, -1, 0], "normal": [0, 1, 0], "size": 0.5, "radiance": 40})]:
        exp = "either"
        if name in ("directional-90", "directional-zero-dir", "disk-radius-0", "sphere-radius-neg",
                    "rect-axes-parallel", "rect-axes-zero"):
            exp = "error"
        if name in ("rect-radiance-negative", "rect-axes-and-size", "rect-tangent-along-normal"):
            exp = "refuse-preferred"
        c.add("json", "light-" + name, args, files=files_of(set_path(base, ("lights",), [lt])), expect=exp,
              names=("scene.json", "lights[0]") if exp == "error" else ())


def texture_scene(tex_name="tex.png", tex=None, extra=None, mat_override=None):
    d = scene_dict()
    d = set_path(d, ("materials", 2, "alphaTexture"), tex_name)
    if mat_override:
        for k, v in mat_override.items():
            d = set_path(d, ("materials", 2, k), v)
    files = {"scene.json": jtext(d)}
    if tex is not None:
        files[tex_name] = tex
    files.update(extra or {})
    return files


def png_surface(c: Cases):
    args = render("scene.json", "--visibility", "v.npy")
    check = sees_scene(vis="v.npy")
    full = TEX
    idat_at = full.index(b"IDAT") - 4
    variants = [
        ("valid", TEX, "ok"),
        ("empty-file", b"", "error"), ("text", b"hello, not a png\n", "error"),
        ("truncated-8", full[:8], "error"), ("truncated-20", full[:20], "error"),
        ("truncated-33", full[:33], "error"), ("truncated-in-idat", full[:idat_at + 20], "error"),
        ("truncated-before-iend", full[:-12], "either"),
        ("ihdr-0x0", png_bytes(0, 0, idat=zlib.compress(b"")), "error"),
        ("ihdr-65535x65535", png_bytes(65535, 65535, idat=zlib.compress(b"\0" * 64)), "error"),
        ("ihdr-2^31-1x1", png_bytes(2147483647, 1, idat=zlib.compress(b"\0" * 64)), "error"),
        ("ihdr-1x2^31-1", png_bytes(1, 2147483647, idat=zlib.compress(b"\0" * 64)), "error"),
        ("ihdr-2^32-1-square", png_bytes(4294967295, 4294967295, idat=zlib.compress(b"\0" * 64)), "error"),
        ("bomb-16384-gray", lambda: png_bytes(16384, 16384, color=0, idat=zero_idat(16384, 16384, 1)), "error"),
        ("bomb-8192-gray", lambda: png_bytes(8192, 8192, color=0, idat=zero_idat(8192, 8192, 1)), "either"),
        ("inflates-past-header", png_bytes(2048, 2048, color=0, idat=zero_idat(2048, 2048, 1, extra_rows=2048)), "either"),
        ("rgba-16bit", png_bytes(16, 16, color=6, depth=16), "either"),
        ("palette-no-plte", png_bytes(16, 16, color=3), "error"),
        ("palette-trns", png_bytes(16, 16, color=3, pre=[png_chunk(b"PLTE", b"\0\0\0\xff\xff\xff"),
                                                         png_chunk(b"tRNS", b"\0\xff")]), "either"),
        ("interlaced-1x1", png_bytes(1, 1, color=6, interlace=1), "either"),
        ("gray-1bit", png_bytes(8, 8, color=0, depth=1, pixels=b"\xaa" * 8), "either"),
        ("gray-alpha", png_bytes(8, 8, color=4), "either"),
        ("bad-crc", full[:29] + b"\0\0\0\0" + full[33:], "either"),
        ("bad-filter-byte", png_bytes(16, 16, filter_byte=7), "error"),
        ("no-idat", full[:33] + png_chunk(b"IEND", b""), "error"),
        ("corrupt-zlib", png_bytes(16, 16, idat=b"\x78\x9c\xff\xff\xff\xff"), "error"),
        ("color-type-5", png_bytes(16, 16, ihdr=struct.pack(">IIBBBBB", 16, 16, 8, 5, 0, 0, 0)), "error"),
        ("bit-depth-3", png_bytes(16, 16, ihdr=struct.pack(">IIBBBBB", 16, 16, 3, 0, 0, 0, 0)), "error"),
        ("jpeg-garbage", b"\xff\xd8\xff\xe0" + b"\0" * 100, "error"),
        ("gif", b"GIF89a\x01\x00\x01\x00\x00\x00\x00,\x00\x00\x00\x00\x01\x00\x01\x00\x00\x02\x02D\x01\x00;", "either"),
    ]
    for name, data, exp in variants:
        budget = BUDGET_LIMIT if name.startswith(("bomb", "inflates")) else BUDGET_SMALL
        c.add("png", name, args, files=texture_scene(tex=data), expect=exp,
              names=("tex.png",) if exp == "error" else (), check=check if exp == "ok" else sees_scene(),
              budget_mb=budget)
    for name, files, exp in [
        ("missing", texture_scene(tex=None), "error"),
        ("directory", texture_scene(extra={"tex.png": Dir()}), "error"),
        ("fifo", texture_scene(extra={"tex.png": Fifo()}), "error"),
        ("dev-zero-link", texture_scene(extra={"tex.png": Symlink("/dev/zero")}), "error"),
        ("dev-null-link", texture_scene(extra={"tex.png": Symlink("/dev/null")}), "error"),
        ("link-loop", texture_scene(extra={"tex.png": Symlink("loop.png"), "loop.png": Symlink("tex.png")}), "error"),
        ("dangling-link", texture_scene(extra={"tex.png": Symlink("gone.png")}), "error"),
        ("empty-name", texture_scene(tex_name=""), "error"),
        ("dot-name", texture_scene(tex_name="."), "error"),
        ("absolute-proc", texture_scene(tex_name="/proc/self/status"), "error"),
        ("control-chars-name", texture_scene(tex_name="\u001b[31mred\n.png"), "error"),
    ]:
        nm = ("tex.png",) if "tex.png" in files and name not in ("empty-name", "dot-name") else ()
        if name == "control-chars-name":
            nm = ("\\x1b",)
        c.add("png", name, args, files=files, expect=exp, names=nm)
    gens = [("chainlink-0", {"generator": "chainlink", "size": 0}, "error"),
            ("chainlink-neg", {"generator": "chainlink", "size": -1}, "error"),
            ("chainlink-1", {"generator": "chainlink", "size": 1}, "either"),
            ("chainlink-8192", {"generator": "chainlink", "size": 8192}, "either"),
            ("chainlink-1e9", {"generator": "chainlink", "size": 1000000000}, "error"),
            ("chainlink-2^31", {"generator": "chainlink", "size": 2147483648}, "error"),
            ("chainlink-1.5", {"generator": "chainlink", "size": 1.5}, "error"),
            ("chainlink-string", {"generator": "chainlink", "size": "64"}, "error"),
            ("leaf-nosize", {"generator": "leaf"}, "either"),
            ("bogus-generator", {"generator": "bogus", "size": 64}, "error"),
            ("no-generator", {"size": 64}, "error"),
            ("extra-key", {"generator": "leaf", "size": 64, "bogus": 1}, "error"),
            ("empty-object", {}, "error")]
    for name, tex, exp in gens:
        d = set_path(scene_dict(), ("materials", 2, "alphaTexture"), tex)
        c.add("png", "generator-" + name, args, files={"scene.json": jtext(d)}, expect=exp,
              names=("scene.json",) if exp == "error" else (), budget_mb=BUDGET_LIMIT)
    gray = png_bytes(16, 16, color=0, pixels=bytes(range(0, 256, 1)))
    for ch in ("alpha", "red", "luminance", "auto"):
        c.add("png", "gray-channel-" + ch, args,
              files=texture_scene(tex=gray, mat_override={"alphaChannel": ch}), expect="either")


CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_QUADS = [(1, 4, 3, 2), (5, 6, 7, 8), (1, 5, 8, 4), (2, 3, 7, 6), (1, 2, 6, 5), (4, 8, 7, 3)]


def cube_obj(mtl="cube.mtl"):
    lines = ["# stsv probe cube", "mtllib " + mtl if mtl else "", "o cube"]
    lines += ["v %g %g %g" % v for v in CUBE_V]
    lines += ["v 2 0.2 0.5", "v 3 0.2 0.5", "v 3 1.2 0.5", "v 2 1.2 0.5"]
    lines += ["vt 0 0", "vt 2 0", "vt 2 2", "vt 0 2"]
    lines += ["usemtl solid"] if mtl else []
    lines += ["f %d %d %d %d" % q for q in CUBE_QUADS]
    lines += ["usemtl grate"] if mtl else []
    lines += ["f 9/1 10/2 11/3 12/4"]
    return "\n".join(ln for ln in lines if ln != "") + "\n"


CUBE_MTL = "newmtl solid\nKd 0.6 0.6 0.6\nnewmtl grate\nKd 0.5 0.5 0.5\nmap_d tex.png\n"


def obj_surface(c: Cases):
    args = render("cube.obj", "--visibility", "v.npy")
    base = cube_obj()

    def files(obj=base, mtl=CUBE_MTL, extra=None):
        f = {"cube.obj": obj, "tex.png": TEX}
        if mtl is not None:
            f["cube.mtl"] = mtl
        f.update(extra or {})
        return f

    c.add("obj", "base", args, files=files(), expect="ok", check=sees_scene(vis="v.npy"))
    first_v = "v 0 0 0"
    for label, x, exp in [("1e38", "1e38", "either"), ("-1e38", "-1e38", "either"),
                          ("1e39", "1e39", "refuse-preferred"), ("1e400", "1e400", "error"),
                          ("nan", "nan", "error"), ("NaN", "NaN", "error"), ("inf", "inf", "error"),
                          ("-inf", "-inf", "error"), ("1e-38", "1e-38", "either"), ("-0", "-0", "either"),
                          ("1e-400", "1e-400", "either"), ("hexfloat", "0x1p3", "either"),
                          ("comma", "1,5", "error"), ("two-dots", "1.5.3", "error"), ("exp-only", "1e", "error"),
                          ("double-minus", "--1", "error"), ("plus", "+1", "either"), ("dot5", ".5", "either"),
                          ("1e9", "1e9", "either"), ("2e9", "2e9", "either")]:
        c.add("obj", "v-" + label, args, files=files(base.replace(first_v, "v %s 0 0" % x, 1)), expect=exp,
              names=("cube.obj", ":") if exp == "error" else (), check=sees_scene())
    for label, line, exp in [("two-coords", "v 0 0", "error"), ("w", "v 0 0 0 1", "either"),
                             ("colors", "v 0 0 0 1 0 0", "either"), ("empty", "v", "error"),
                             ("seven", "v 0 0 0 1 2 3 4", "refuse-preferred")]:
        c.add("obj", "v-line-" + label, args, files=files(base.replace(first_v, line, 1)), expect=exp,
              names=("cube.obj",) if exp == "error" else ())
    first_vt = "vt 0 0"
    for label, x, exp in [("1e30", "1e30", "either"), ("-1e30", "-1e30", "either"),
                          ("1e38", "1e38", "either"), ("3e9", "3e9", "either"), ("-3e9", "-3e9", "either"),
                          ("2^31", "2147483648", "either"), ("1e9", "1e9", "either"),
                          ("nan", "nan", "error"), ("inf", "inf", "error"), ("1e39", "1e39", "refuse-preferred")]:
        for clamp in ("", "-clamp on "):
            mtl = CUBE_MTL.replace("map_d tex.png", "map_d %stex.png" % clamp)
            c.add("obj", "vt-%s%s" % (label, "-clamp" if clamp else ""), args,
                  files=files(base.replace(first_vt, "vt %s %s" % (x, x), 1), mtl), expect=exp,
                  names=("cube.obj",) if exp == "error" else (), check=sees_scene())
    for label, line, exp in [("one", "vt 0.5", "either"), ("three", "vt 0 0 0", "either"), ("empty", "vt", "error")]:
        c.add("obj", "vt-line-" + label, args, files=files(base.replace(first_vt, line, 1)), expect=exp)
    first_f = "f 1 4 3 2"
    for label, line, exp in [
            ("repeated-all", "f 1 1 1", "ok"), ("repeated-quad", "f 1 2 2 3", "ok"), ("zero", "f 0 1 2", "error"),
            ("out-of-range", "f 1 2 99", "error"), ("relative", "f -12 -9 -10", "ok"),
            ("relative-out", "f -99 1 2", "error"), ("two", "f 1 2", "error"), ("one", "f 1", "error"),
            ("empty", "f", "error"), ("vt-out", "f 1/99 2/1 3/1", "error"), ("vn-missing", "f 1//1 2//1 3//1", "refuse-preferred"),
            ("four-slashes", "f 1/1/1/1 2 3", "error"), ("2^31", "f 2147483648 1 2", "error"),
            ("2^64", "f 18446744073709551616 1 2", "error"), ("fraction", "f 1.5 2 3", "error"),
            ("letters", "f a b c", "error"), ("trailing-slash", "f 1/ 2/ 3/", "either"),
            ("comment", "f 1 4 3 2 # comment", "ok"), ("mixed-vt", "f 1/1 2 3", "either"),
            ("forward", "f 1 2 13", "error"), ("negative-zero", "f -0 1 2", "error")]:
        c.add("obj", "f-" + label, args, files=files(base.replace(first_f, line, 1)), expect=exp,
              names=("cube.obj", ":") if exp == "error" else (),
              check=sees_scene() if exp != "error" else None)
    # Huge faces.
    def polygon(n=200000):
        import math
        circle = ["v %.6f 0.5 %.6f" % (math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)) for i in range(n)]
        return ("\n".join(circle) + "\nf " + " ".join(str(i + 1) for i in range(n)) + "\n").encode()

    c.add("obj", "polygon-200000", render("big.obj"), files={"big.obj": polygon},
          budget_mb=BUDGET_LIMIT, check=sees_scene(), timeout=120)
    c.add("obj", "face-1e6-repeated", render("big.obj"),
          files={"big.obj": lambda: ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf " + " ".join(["1 2 3"] * 333334) + "\n").encode()},
          budget_mb=BUDGET_LIMIT)
    tri = "".join("f %d %d %d\nf %d %d %d\n" % (q[0], q[1], q[2], q[0], q[2], q[3]) for q in CUBE_QUADS)
    c.add("obj", "cube-x83334", render("big.obj"),
          files={"big.obj": lambda: ("\n".join("v %g %g %g" % v for v in CUBE_V) + "\n" + tri * 83334).encode()},
          budget_mb=BUDGET_LIMIT, desc="a million triangles: 2.6 GB at 2.6 KB a triangle, above --max-memory 1G")
    c.add("obj", "comment-20MB", args, files=files(lambda: ("#" + "x" * (20 * MiB) + "\n" + base).encode()), check=sees_scene(),
          budget_mb=BUDGET_LIMIT)
    c.add("obj", "v-line-1e6-numbers", args, files=files(base.replace(first_v, "v " + " 1" * 1000000, 1)),
          expect="refuse-preferred")
    # MTL.
    for label, obj, mtl, extra, exp, nm in [
            ("mtllib-missing", base.replace("mtllib cube.mtl", "mtllib none.mtl"), None, None, "error", ("none.mtl",)),
            ("mtllib-directory", base, None, {"cube.mtl": Dir()}, "error", ("cube.mtl",)),
            ("mtllib-fifo", base, None, {"cube.mtl": Fifo()}, "error", ("cube.mtl",)),
            ("mtllib-dev-zero", base, None, {"cube.mtl": Symlink("/dev/zero")}, "error", ("cube.mtl",)),
            ("mtllib-empty-name", base.replace("mtllib cube.mtl", "mtllib"), CUBE_MTL, None, "error", ("cube.obj",)),
            ("usemtl-undefined", base.replace("usemtl solid", "usemtl nope"), CUBE_MTL, None, "error", ("nope",)),
            ("kd-nan", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd nan 0 0"), None, "error", ("cube.mtl",)),
            ("kd-1e38", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd 1e38 1e38 1e38"), None, "refuse-preferred", ()),
            ("kd-negative", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd -1 -1 -1"), None, "refuse-preferred", ()),
            ("kd-one", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd 0.5"), None, "either", ()),
            ("kd-empty", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd"), None, "error", ("cube.mtl",)),
            ("map-d-missing", base, CUBE_MTL.replace("map_d tex.png", "map_d none.png"), None, "error", ("none.png",)),
            ("map-d-directory", base, CUBE_MTL.replace("map_d tex.png", "map_d d.png"), {"d.png": Dir()}, "error", ("d.png",)),
            ("map-d-fifo", base, CUBE_MTL.replace("map_d tex.png", "map_d f.png"), {"f.png": Fifo()}, "error", ("f.png",)),
            ("map-d-huge-header", base, CUBE_MTL.replace("map_d tex.png", "map_d h.png"),
             {"h.png": png_bytes(65535, 65535, idat=zlib.compress(b"\0" * 64))}, "error", ("h.png",)),
            ("map-d-truncated", base, CUBE_MTL.replace("map_d tex.png", "map_d t.png"), {"t.png": TEX[:40]}, "error", ("t.png",)),
            ("map-d-no-file", base, CUBE_MTL.replace("map_d tex.png", "map_d"), None, "error", ("cube.mtl",)),
            ("map-d-imfchan-r", base, CUBE_MTL.replace("map_d tex.png", "map_d -imfchan r tex.png"), None, "ok", ()),
            ("map-d-imfchan-z", base, CUBE_MTL.replace("map_d tex.png", "map_d -imfchan z tex.png"), None, "either", ()),
            ("map-d-imfchan-q", base, CUBE_MTL.replace("map_d tex.png", "map_d -imfchan q tex.png"), None, "refuse-preferred", ()),
            ("map-d-clamp-maybe", base, CUBE_MTL.replace("map_d tex.png", "map_d -clamp maybe tex.png"), None, "refuse-preferred", ()),
            ("map-d-clamp-no-value", base, CUBE_MTL.replace("map_d tex.png", "map_d -clamp"), None, "error", ("cube.mtl",)),
            ("map-d-other-option", base, CUBE_MTL.replace("map_d tex.png", "map_d -o 1e38 1e38 tex.png"), None, "either", ()),
            ("map-kd-missing-beside-map-d", base, CUBE_MTL + "map_Kd none.png\n", None, "refuse-preferred", ()),
            ("map-kd-missing-no-map-d", base, CUBE_MTL.replace("Kd 0.6 0.6 0.6", "Kd 0.6 0.6 0.6\nmap_Kd none.png"), None,
             "error", ("none.png",)),
            ("newmtl-duplicate", base, CUBE_MTL + "newmtl solid\nKd 0.1 0.1 0.1\n", None, "either", ()),
            ("newmtl-empty", base, CUBE_MTL + "newmtl\n", None, "error", ("cube.mtl",)),
            ("mtl-crlf", base, CUBE_MTL.replace("\n", "\r\n"), None, "ok", ()),
            ("mtl-nul", base, CUBE_MTL.replace("Kd 0.6", "Kd 0\0.6"), None, "error", ("cube.mtl",)),
            ("mtl-d-and-tr", base, CUBE_MTL + "d 0\nTr 1\n", None, "ok", ())]:
        c.add("obj", label, args, files=files(obj, mtl, extra), expect=exp,
              names=nm, check=sees_scene() if exp != "error" else None)
    for label, obj, exp in [
            ("crlf", base.replace("\n", "\r\n"), "ok"), ("bom", "\ufeff" + base, "either"),
            ("no-final-newline", base.rstrip("\n"), "ok"), ("tabs", base.replace(" ", "\t"), "ok"),
            ("nul-in-v", base.replace(first_v, "v 0 0\0 0", 1), "error"),
            ("continuation", base.replace(first_f, "f 1 4 \\\n3 2", 1), "either"),
            ("groups", base.replace("o cube", "o cube\ng side\ns 1\nvn 0 0 1"), "ok"),
            ("line-element", base + "l 1 2\n", "either"), ("point-element", base + "p 1\n", "either"),
            ("unknown-statement", base + "bogus 0 1 1 2\n", "error"), ("curv-statement", base + "curv 0 1 1 2\n", "either"),
            ("no-faces", "\n".join(ln for ln in base.splitlines() if not ln.startswith("f")) + "\n", "error"),
            ("empty", "", "error"), ("binary", "\0\1\2\3" * 1000, "error")]:
        c.add("obj", "file-" + label, args, files=files(obj), expect=exp,
              names=("cube.obj",) if exp == "error" else (), check=sees_scene() if exp != "error" else None)
    for label, f, exp in [("directory", {"cube.obj": Dir()}, "error"), ("fifo", {"cube.obj": Fifo()}, "error"),
                          ("dev-zero", {"cube.obj": Symlink("/dev/zero")}, "error"),
                          ("upper-ext", {"cube.OBJ": base, "cube.mtl": CUBE_MTL, "tex.png": TEX}, "either")]:
        a = render("cube.OBJ") if label == "upper-ext" else render("cube.obj")
        c.add("obj", "scene-" + label, a, files=f, expect=exp, names=("cube.obj",) if exp == "error" else ())
    # An OBJ inside a JSON scene.
    d = set_path(scene_dict(), ("meshes", 2), {"file": "cube.obj", "transform": {"translate": [-1.5, 0, 1.5]}})
    jf = {"scene.json": jtext(d), "cube.obj": base, "cube.mtl": CUBE_MTL, "tex.png": TEX}
    c.add("obj", "in-json", render("scene.json"), files=jf, expect="ok", check=sees_scene())
    for label, fname, extra, exp in [("file-empty", "", {}, "error"), ("file-dot", ".", {}, "error"),
                                     ("file-missing", "none.obj", {}, "error"),
                                     ("file-directory", "d.obj", {"d.obj": Dir()}, "error"),
                                     ("file-fifo", "f.obj", {"f.obj": Fifo()}, "error"),
                                     ("file-dev-zero", "z.obj", {"z.obj": Symlink("/dev/zero")}, "error"),
                                     ("file-self", "scene.json", {}, "error"),
                                     ("file-ply", "x.ply", {"x.ply": "ply\n"}, "error"),
                                     ("file-no-ext", "cube", {"cube": base}, "error"),
                                     ("file-absolute-proc", "/proc/self/status", {}, "error")]:
        dd = set_path(d, ("meshes", 2, "file"), fname)
        ff = dict(jf, **extra)
        ff["scene.json"] = jtext(dd)
        c.add("obj", "json-" + label, render("scene.json"), files=ff, expect=exp,
              names=("scene.json",) if exp == "error" else ())


TETRA_OFF = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
CUBE_OFF = ("OFF\n8 6 0\n" + "".join("%g %g %g\n" % v for v in CUBE_V)
            + "".join("4 %d %d %d %d\n" % tuple(i - 1 for i in q) for q in CUBE_QUADS))


def off_surface(c: Cases):
    args = render("m.off", "--visibility", "v.npy")
    c.add("off", "base", args, files={"m.off": CUBE_OFF}, expect="ok", check=sees_scene(vis="v.npy"))
    c.add("off", "tetrahedron", args, files={"m.off": TETRA_OFF}, expect="ok", check=sees_scene(),
          desc="its shadow falls behind it, out of view")
    body = TETRA_OFF.split("\n", 2)[2]
    for label, text, exp in [
            ("counts-on-header", "OFF 4 4 0\n" + body, "ok"),
            ("coff", "COFF\n4 4 0\n" + "".join(ln + " 255 0 0 255\n" for ln in TETRA_OFF.splitlines()[2:6])
             + "\n".join(TETRA_OFF.splitlines()[6:]) + "\n", "ok"),
            ("noff", "NOFF\n4 4 0\n" + "".join(ln + " 0 0 1\n" for ln in TETRA_OFF.splitlines()[2:6])
             + "\n".join(TETRA_OFF.splitlines()[6:]) + "\n", "ok"),
            ("stoff", "STOFF\n4 4 0\n" + "".join(ln + " 0.5 0.5\n" for ln in TETRA_OFF.splitlines()[2:6])
             + "\n".join(TETRA_OFF.splitlines()[6:]) + "\n", "ok"),
            ("comments", "# c\nOFF\n# d\n4 4 0\n" + body, "ok"),
            ("crlf", TETRA_OFF.replace("\n", "\r\n"), "ok"),
            ("binary", "OFF BINARY\n" + "\0" * 100, "error"),
            ("counts-2e9", "OFF\n2000000000 1 0\n" + body, "error"),
            ("faces-2e9", "OFF\n4 2000000000 0\n" + body, "error"),
            ("counts-2^32", "OFF\n4294967296 4 0\n" + body, "error"),
            ("counts-negative", "OFF\n-4 4 0\n" + body, "error"),
            ("faces-negative", "OFF\n4 -4 0\n" + body, "error"),
            ("counts-float", "OFF\n4.5 4 0\n" + body, "error"),
            ("counts-missing", "OFF\n" + body, "error"),
            ("truncated-vertices", "OFF\n5 4 0\n" + body, "error"),
            ("truncated-faces", "OFF\n4 5 0\n" + body, "error"),
            ("face-out-of-range", TETRA_OFF.replace("3 1 2 3", "3 1 2 99"), "error"),
            ("face-negative", TETRA_OFF.replace("3 1 2 3", "3 1 2 -1"), "error"),
            ("face-count-0", TETRA_OFF.replace("3 1 2 3", "0"), "error"),
            ("face-count-1", TETRA_OFF.replace("3 1 2 3", "1 0"), "error"),
            ("face-count-2", TETRA_OFF.replace("3 1 2 3", "2 0 1"), "error"),
            ("face-count-4e9", TETRA_OFF.replace("3 1 2 3", "4000000000 0 1 2"), "error"),
            ("face-count-100000-short", TETRA_OFF.replace("3 1 2 3", "100000 0 1 2"), "error"),
            ("face-repeated", TETRA_OFF.replace("3 1 2 3", "3 1 1 1"), "ok"),
            ("coord-nan", TETRA_OFF.replace("1 0 0\n", "nan 0 0\n", 1), "error"),
            ("coord-1e39", TETRA_OFF.replace("1 0 0\n", "1e39 0 0\n", 1), "refuse-preferred"),
            ("coord-1e400", TETRA_OFF.replace("1 0 0\n", "1e400 0 0\n", 1), "error"),
            ("coord-letters", TETRA_OFF.replace("1 0 0\n", "x 0 0\n", 1), "error"),
            ("empty", "", "error"), ("only-header", "OFF\n", "error"), ("no-header", body, "either"),
            ("4off", "4OFF\n4 4 0\n" + "".join(ln + " 1\n" for ln in TETRA_OFF.splitlines()[2:6])
             + "\n".join(TETRA_OFF.splitlines()[6:]) + "\n", "either"),
            ("noff-short-normals", "NOFF\n4 4 0\n" + body, "error"),
            ("edges-garbage", "OFF\n4 4 x\n" + body, "either"),
            ("extra-data", TETRA_OFF + "1 2 3\n", "either"),
            ("zero-area", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n", "either")]:
        c.add("off", label, args, files={"m.off": text}, expect=exp, names=("m.off",) if exp == "error" else (),
              check=sees_scene() if exp != "error" else None)
    c.add("off", "declared-huge-face", args, files={"m.off": "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2000000000 0 1 2\n"},
          expect="error", names=("m.off",))
    c.add("off", "vertices-1e6-unused", args,
          files={"m.off": lambda: ("OFF\n1000000 1 0\n" + "".join("%d 0 %d\n" % (i % 1000, i // 1000) for i in range(1000000))
                                   + "3 0 1 1000\n").encode()},
          expect="either", budget_mb=BUDGET_LIMIT)
    for label, f in [("directory", {"m.off": Dir()}), ("fifo", {"m.off": Fifo()}), ("dev-zero", {"m.off": Symlink("/dev/zero")})]:
        c.add("off", "scene-" + label, args, files=f, expect="error", names=("m.off",))


# ----------------------------------------------------------------------------------------------
# glTF: a unit cube (8 vertices, 12 triangles, TEXCOORD_0), optionally alpha-textured and skinned

def cube_buffer(skin=False):
    pos = b"".join(struct.pack("<3f", *v) for v in CUBE_V)
    uv = b"".join(struct.pack("<2f", v[0], v[2]) for v in CUBE_V)
    tris = []
    for q in CUBE_QUADS:
        a, b, cc, dd = (i - 1 for i in q)
        tris += [a, b, cc, a, cc, dd]
    idx = struct.pack("<36H", *tris)
    data = pos + uv + idx                       # 96 + 64 + 72 = 232
    if skin:
        data += bytes([0, 0, 0, 0] * 8)         # JOINTS_0, u8 VEC4: 32 bytes at 232
        data += struct.pack("<4f", 1, 0, 0, 0) * 8  # WEIGHTS_0: 128 bytes at 264
        data += struct.pack("<16f", *[1 if i % 5 == 0 else 0 for i in range(16)])  # IBM at 392
    return data


def data_uri(b: bytes) -> str:
    return "data:application/octet-stream;base64," + base64.b64encode(b).decode()


def gltf_doc(texture=False, skin=False, uri=None):
    buf = cube_buffer(skin)
    doc = {
        "asset": {"version": "2.0", "generator": "stsv probe"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                    "material": 0, "mode": 4}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 8, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 36, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 96},
            {"buffer": 0, "byteOffset": 96, "byteLength": 64},
            {"buffer": 0, "byteOffset": 160, "byteLength": 72},
        ],
        "buffers": [{"byteLength": len(buf), "uri": uri if uri is not None else data_uri(buf)}],
    }
    if texture:
        doc["materials"][0].update({"alphaMode": "MASK", "alphaCutoff": 0.5,
                                    "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                             "baseColorTexture": {"index": 0}}})
        doc["textures"] = [{"source": 0, "sampler": 0}]
        doc["images"] = [{"uri": "tex.png"}]
        doc["samplers"] = [{"wrapS": 10497, "wrapT": 10497}]
    if skin:
        doc["accessors"] += [
            {"bufferView": 3, "componentType": 5121, "count": 8, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 8, "type": "VEC4"},
            {"bufferView": 5, "componentType": 5126, "count": 1, "type": "MAT4"},
        ]
        doc["bufferViews"] += [{"buffer": 0, "byteOffset": 232, "byteLength": 32},
                               {"buffer": 0, "byteOffset": 264, "byteLength": 128},
                               {"buffer": 0, "byteOffset": 392, "byteLength": 64}]
        doc["meshes"][0]["primitives"][0]["attributes"].update({"JOINTS_0": 3, "WEIGHTS_0": 4})
        doc["nodes"] = [{"mesh": 0, "skin": 0}, {"translation": [0, 0.5, 0]}]
        doc["scenes"] = [{"nodes": [0, 1]}]
        doc["skins"] = [{"joints": [1], "inverseBindMatrices": 5}]
    return doc


def glb_bytes(doc, bin_data: bytes | None, version=2, magic=b"glTF", json_kind=b"JSON", length=None,
              json_len=None, bin_len=None) -> bytes:
    j = jtext(doc).encode()
    j += b" " * ((4 - len(j) % 4) % 4)
    out = struct.pack("<I", len(j) if json_len is None else json_len) + json_kind + j
    if bin_data is not None:
        b = bin_data + b"\0" * ((4 - len(bin_data) % 4) % 4)
        out += struct.pack("<I", len(b) if bin_len is None else bin_len) + b"BIN\0" + b
    total = 12 + len(out)
    return magic + struct.pack("<II", version, total if length is None else length) + out


def gltf_surface(c: Cases):
    args = render("m.gltf", "--visibility", "v.npy")
    check_ok = sees_scene(vis="v.npy")

    def add(name, doc, exp="error", extra=None, names=None, a=None, check=None, **kw):
        files = {"m.gltf": doc if isinstance(doc, (str, bytes)) or callable(doc) else jtext(doc), "tex.png": TEX}
        files.update(extra or {})
        if names is None:
            names = ("m.gltf",) if exp == "error" else ()
        c.add("gltf", name, a or args, files=files, expect=exp, names=names,
              check=check if check is not None else (sees_scene() if exp != "error" else None), **kw)

    base = gltf_doc()
    tex = gltf_doc(texture=True)
    add("base", base, "ok", check=check_ok)
    add("base-textured", tex, "ok", check=check_ok)
    add("base-skinned", gltf_doc(skin=True), "ok", check=check_ok)
    buf = cube_buffer()
    add("external-bin", gltf_doc(uri="m.bin"), "ok", extra={"m.bin": buf}, check=check_ok)
    c.add("gltf", "glb", render("m.glb", "--visibility", "v.npy"),
          files={"m.glb": glb_bytes(del_path(gltf_doc(), ("buffers", 0, "uri")), buf)}, expect="ok",
          check=check_ok)

    # Node trees.
    add("node-shared-child", set_path(set_path(base, ("nodes",), [{"children": [2]}, {"children": [2]}, {"mesh": 0}]),
                                      ("scenes", 0, "nodes"), [0, 1]), names=("m.gltf", "node 2"))
    add("node-child-twice", set_path(base, ("nodes",), [{"children": [1, 1]}, {"mesh": 0}]), names=("m.gltf", "node 1"))
    add("scene-node-twice", set_path(base, ("scenes", 0, "nodes"), [0, 0]), names=("m.gltf", "node 0"))
    add("node-self-cycle", set_path(base, ("nodes",), [{"mesh": 0, "children": [0]}]), names=("m.gltf", "node 0"))
    add("node-two-cycle", set_path(base, ("nodes",), [{"mesh": 0, "children": [1]}, {"children": [0]}]))
    add("node-cycle-off-scene", set_path(base, ("nodes",), [{"mesh": 0}, {"children": [2]}, {"children": [1]}]),
        "either", desc="a cycle among nodes no scene reaches")
    for depth, exp in [(256, "ok"), (300, "error"), (100000, "error")]:
        nodes = [{"children": [i + 1]} for i in range(depth - 1)] + [{"mesh": 0}]
        add("node-chain-%d" % depth, set_path(base, ("nodes",), nodes), exp, check=check_ok if exp == "ok" else None)
    def instances():
        nodes = [{"mesh": 0, "translation": [i % 500 * 2.0, 0, i // 500 * 2.0]} for i in range(200000)]
        return jtext(set_path(set_path(base, ("nodes",), nodes), ("scenes", 0, "nodes"), list(range(200000)))).encode()

    add("instances-200000", instances,
        "error", desc="2.4 M triangles as instances: 6 GB at 2.6 KB a triangle, above --max-memory 1G",
        budget_mb=BUDGET_LIMIT)
    fan = [{"children": list(range(1, 1001))}] + [{"mesh": 0}] * 1000
    add("instances-fanout-1000", set_path(base, ("nodes",), fan), "either", budget_mb=BUDGET_LIMIT)
    add("node-mesh-out-of-range", set_path(base, ("nodes", 0, "mesh"), 5), names=("m.gltf", "mesh"))
    add("node-child-out-of-range", set_path(base, ("nodes", 0, "children"), [99]))
    add("node-child-negative", set_path(base, ("nodes", 0, "children"), [-1]))
    add("scene-out-of-range", set_path(base, ("scene",), 5))
    add("scene-negative", set_path(base, ("scene",), -1), "refuse-preferred")
    add("scenes-empty", set_path(base, ("scenes",), []))
    add("no-scenes", del_path(del_path(base, ("scene",)), ("scenes",)), "either")
    add("nodes-empty", set_path(base, ("nodes",), []))
    for label, m, exp in [("zeros", [0] * 16, "error"), ("1e38", [1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1], "error"),
                          ("15-elements", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0], "error"),
                          ("1e400", [Raw("1e400")] + [0] * 15, "error"),
                          ("projective", [1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1], "either")]:
        add("matrix-" + label, set_path(base, ("nodes", 0, "matrix"), m), exp,
            desc="a matrix of 15 numbers: tinygltf drops it and the node keeps the identity" if label == "15-elements" else "")
    for label, key, v, exp in [("translation-1e8", "translation", [1e8, 0, 0], "either"),
                               ("translation-2e9", "translation", [2e9, 0, 0], "error"),
                               ("rotation-zero", "rotation", [0, 0, 0, 0], "either"),
                               ("rotation-unnormalized", "rotation", [0, 0, 0, 5], "either"),
                               ("scale-zero", "scale", [0, 0, 0], "error"),
                               ("scale-1e20", "scale", [1e20, 1e20, 1e20], "error"),
                               ("scale-negative", "scale", [-1, 1, 1], "either"),
                               ("translation-string", "translation", "x", "error")]:
        add("node-" + label, set_path(base, ("nodes", 0, key), v), exp)

    # Accessors and buffer views.
    for label, path, v, exp in [
            ("pos-count-2^31", ("accessors", 0, "count"), 2147483647, "error"),
            ("pos-count-0", ("accessors", 0, "count"), 0, "error"),
            ("pos-count-9", ("accessors", 0, "count"), 9, "error"),
            ("pos-offset-1e9", ("accessors", 0, "byteOffset"), 1000000000, "error"),
            ("pos-offset-misaligned", ("accessors", 0, "byteOffset"), 2, "error"),
            ("pos-ubyte", ("accessors", 0, "componentType"), 5121, "error"),
            ("pos-byte", ("accessors", 0, "componentType"), 5120, "error"),
            ("pos-bogus-type", ("accessors", 0, "componentType"), 5127, "error"),
            ("pos-vec2", ("accessors", 0, "type"), "VEC2", "error"),
            ("pos-mat4", ("accessors", 0, "type"), "MAT4", "error"),
            ("pos-normalized", ("accessors", 0, "normalized"), True, "either"),
            ("pos-view-99", ("accessors", 0, "bufferView"), 99, "error"),
            ("pos-view-negative", ("accessors", 0, "bufferView"), -1, "error"),
            ("pos-sparse", ("accessors", 0, "sparse"), {"count": 1, "indices": {"bufferView": 2, "componentType": 5123},
                                                        "values": {"bufferView": 0}}, "error"),
            ("pos-min-max-wrong", ("accessors", 0, "max"), [0.1, 0.1, 0.1], "either"),
            ("view-stride-4", ("bufferViews", 0, "byteStride"), 4, "error"),
            ("view-stride-252", ("bufferViews", 0, "byteStride"), 252, "error"),
            ("view-stride-1e9", ("bufferViews", 0, "byteStride"), 1000000000, "error"),
            ("view-length-beyond", ("bufferViews", 0, "byteLength"), 100000, "error"),
            ("view-offset-beyond", ("bufferViews", 0, "byteOffset"), 4294967295, "error"),
            ("view-buffer-99", ("bufferViews", 0, "buffer"), 99, "error"),
            ("buffer-length-beyond", ("buffers", 0, "byteLength"), 100000, "error"),
            ("buffer-length-2^40", ("buffers", 0, "byteLength"), 1 << 40, "error"),
            ("buffer-length-negative", ("buffers", 0, "byteLength"), -1, "error"),
            ("indices-float", ("accessors", 2, "componentType"), 5126, "error"),
            ("indices-count-35", ("accessors", 2, "count"), 35, "either"),
            ("indices-count-2^32", ("accessors", 2, "count"), 4294967296, "error"),
            ("indices-vec3", ("accessors", 2, "type"), "VEC3", "error"),
            ("indices-accessor-99", ("meshes", 0, "primitives", 0, "indices"), 99, "error"),
            ("position-accessor-99", ("meshes", 0, "primitives", 0, "attributes", "POSITION"), 99, "error"),
            ("no-position", ("meshes", 0, "primitives", 0, "attributes"), {"TEXCOORD_0": 1}, "error"),
            ("primitives-empty", ("meshes", 0, "primitives"), [], "error"),
            ("material-99", ("meshes", 0, "primitives", 0, "material"), 99, "error")]:
        add("acc-" + label, set_path(base, path, v), exp)
    oob = cube_buffer()[:160] + struct.pack("<36H", *([0, 1, 99] * 12))
    add("acc-indices-out-of-range", gltf_doc(uri=data_uri(oob)), "error")
    add("acc-no-buffer-view", del_path(base, ("accessors", 0, "bufferView")), "error",
        desc="all-zero positions: no triangle with area")
    for mode in range(-1, 8):
        exp = "ok" if mode in (4, 5, 6) else ("refuse-preferred" if mode == -1 else "error")
        add("mode-%d" % mode, set_path(base, ("meshes", 0, "primitives", 0, "mode"), mode), exp)
    add("mode-string", set_path(base, ("meshes", 0, "primitives", 0, "mode"), "4"), "refuse-preferred")
    two_prims = set_path(base, ("meshes", 0, "primitives"),
                         [dict(base["meshes"][0]["primitives"][0]), dict(base["meshes"][0]["primitives"][0], mode=1)])
    add("mode-triangles-and-lines", two_prims, "ok", desc="lines skipped with a warning")

    # Texture coordinate sets and KHR_texture_transform.
    tc = ("materials", 0, "pbrMetallicRoughness", "baseColorTexture")
    add("texcoord-1-missing", set_path(tex, tc + ("texCoord",), 1), "error", names=("m.gltf", "TEXCOORD_1"))
    t1 = set_path(set_path(tex, tc + ("texCoord",), 1), ("meshes", 0, "primitives", 0, "attributes", "TEXCOORD_1"), 1)
    add("texcoord-1-present", t1, "ok")
    add("texcoord-99", set_path(tex, tc + ("texCoord",), 99), "error")
    add("texcoord-negative", set_path(tex, tc + ("texCoord",), -1), "error")
    add("texcoord0-count-4", set_path(tex, ("accessors", 1, "count"), 4), "error")
    add("texcoord0-vec3", set_path(tex, ("accessors", 1, "type"), "VEC3"), "error")
    add("texcoord0-ubyte-unnormalized", set_path(tex, ("accessors", 1, "componentType"), 5121), "error")
    add("texcoord0-missing", del_path(tex, ("meshes", 0, "primitives", 0, "attributes", "TEXCOORD_0")), "error")
    for label, ext, exp in [("scale-1e38", {"scale": [1e38, 1e38]}, "either"), ("offset-1e30", {"offset": [1e30, -1e30]}, "either"),
                            ("rotation-1e30", {"rotation": 1e30}, "either"), ("scale-zero", {"scale": [0, 0]}, "either"),
                            ("texcoord-5", {"texCoord": 5}, "error"), ("scale-string", {"scale": "x"}, "error"),
                            ("scale-one", {"scale": [1]}, "error"), ("offset-1e400", {"offset": [Raw("1e400"), 0]}, "error")]:
        d = set_path(tex, tc + ("extensions",), {"KHR_texture_transform": ext})
        d["extensionsUsed"] = ["KHR_texture_transform"]
        add("khr-transform-" + label, d, exp)
    for label, req, exp in [("draco", ["KHR_draco_mesh_compression"], "error"), ("transform", ["KHR_texture_transform"], "ok"),
                            ("bogus", ["EXT_bogus"], "error"), ("not-array", "KHR_texture_transform", "either"),
                            ("not-array-draco", "KHR_draco_mesh_compression", "error"),
                            ("empty", [], "ok"), ("basisu", ["KHR_texture_basisu"], "error")]:
        d = set_path(base, ("extensionsRequired",), req)
        d["extensionsUsed"] = req if isinstance(req, list) else [req]
        add("ext-required-" + label, d, exp, names=("m.gltf",) + ((req[0],) if exp == "error" and isinstance(req, list) else ()))
    add("ext-used-bogus", set_path(base, ("extensionsUsed",), ["EXT_bogus"]), "ok")
    for label, asset, exp in [("1.0", {"version": "1.0"}, "error"), ("3.0", {"version": "3.0"}, "error"),
                              ("2.1", {"version": "2.1"}, "ok"), ("min-2.1", {"version": "2.1", "minVersion": "2.1"}, "error"),
                              ("no-version", {}, "error"), ("number", {"version": 2}, "error"),
                              ("garbage", {"version": "two"}, "error"), ("2.0.1", {"version": "2.0.1"}, "either")]:
        add("version-" + label, set_path(base, ("asset",), asset), exp)
    add("no-asset", del_path(base, ("asset",)), "error")

    # Buffer URIs.
    for label, uri, extra, exp in [
            ("dot", ".", {}, "error"), ("empty", "", {}, "error"), ("dotdot", "..", {}, "error"),
            ("slash", "/", {}, "error"), ("missing", "none.bin", {}, "error"),
            ("directory", "d.bin", {"d.bin": Dir()}, "error"), ("fifo", "f.bin", {"f.bin": Fifo()}, "error"),
            ("dev-zero", "z.bin", {"z.bin": Symlink("/dev/zero")}, "error"),
            ("proc", "/proc/self/status", {}, "error"),
            ("bad-base64", "data:application/octet-stream;base64,!!!!", {}, "error"),
            ("data-empty", "data:,", {}, "error"),
            ("data-short", data_uri(cube_buffer()[:100]), {}, "error"),
            ("data-wrong-mime", "data:image/png;base64," + base64.b64encode(cube_buffer()).decode(), {}, "either"),
            ("escaped-space", "m%20x.bin", {"m x.bin": cube_buffer()}, "either"),
            ("file-scheme", "file:///etc/passwd", {}, "error"),
            ("http", "http://127.0.0.1:9/x.bin", {}, "error"),
            ("short-file", "s.bin", {"s.bin": cube_buffer()[:100]}, "error")]:
        names_uri = label in ("dot", "empty", "dotdot", "slash", "missing", "directory", "fifo", "dev-zero", "proc",
                              "file-scheme", "http")
        add("buffer-uri-" + label, gltf_doc(uri=uri), exp, extra=extra,
            names=("m.gltf", "buffer 0") if names_uri else ("m.gltf",),
            desc="docs: URIs that name no regular file are stsv's errors, naming the buffer" if names_uri else "")

    # Images and materials (the textured cube).
    for label, img, extra, exp in [
            ("missing", {"uri": "none.png"}, {}, "error"), ("empty", {"uri": ""}, {}, "error"),
            ("directory", {"uri": "d.png"}, {"d.png": Dir()}, "error"), ("fifo", {"uri": "f.png"}, {"f.png": Fifo()}, "error"),
            ("dev-zero", {"uri": "z.png"}, {"z.png": Symlink("/dev/zero")}, "error"), ("dot", {"uri": "."}, {}, "error"),
            ("huge-header", {"uri": "data:image/png;base64," + base64.b64encode(
                png_bytes(65535, 65535, idat=zlib.compress(b"\0" * 64))).decode()}, {}, "error"),
            ("truncated", {"uri": "t.png"}, {"t.png": TEX[:40]}, "error"),
            ("jpeg-garbage", {"uri": "j.jpg"}, {"j.jpg": b"\xff\xd8\xff\xe0" + b"\0" * 100}, "error"),
            ("buffer-view-99", {"bufferView": 99, "mimeType": "image/png"}, {}, "error"),
            ("no-source", {}, {}, "error")]:
        add("image-" + label, set_path(tex, ("images", 0), img), exp, extra=extra)
    for label, path, v, exp in [
            ("texture-source-99", ("textures", 0, "source"), 99, "error"),
            ("texture-index-99", tc + ("index",), 99, "error"),
            ("sampler-99", ("textures", 0, "sampler"), 99, "error"),
            ("wrap-mirrored", ("samplers", 0, "wrapS"), 33648, "error"),
            ("wrap-mixed", ("samplers", 0, "wrapS"), 33071, "error"),
            ("wrap-bogus", ("samplers", 0, "wrapS"), 1234, "error"),
            ("alpha-mode-bogus", ("materials", 0, "alphaMode"), "FOO", "error"),
            ("alpha-cutoff-negative", ("materials", 0, "alphaCutoff"), -1, "either"),
            ("alpha-cutoff-nan", ("materials", 0, "alphaCutoff"), Raw("NaN"), "error"),
            ("base-color-2", ("materials", 0, "pbrMetallicRoughness", "baseColorFactor"), [1, 1], "refuse-preferred"),
            ("base-color-2.0", ("materials", 0, "pbrMetallicRoughness", "baseColorFactor"), [2, 2, 2, 2], "either"),
            ("blend", ("materials", 0, "alphaMode"), "BLEND", "ok")]:
        add("material-" + label, set_path(tex, path, v), exp)
    add("materials-empty", set_path(base, ("materials",), []), "error")

    # Skins and morph targets.
    sk = gltf_doc(skin=True)
    for label, path, v, exp in [
            ("joints-out-of-range", ("skins", 0, "joints"), [99], "error"),
            ("joint-is-mesh-node", ("skins", 0, "joints"), [0], "either"),
            ("ibm-count-mismatch", ("accessors", 5, "count"), 3, "error"),
            ("skin-99", ("nodes", 0, "skin"), 99, "error"),
            ("joints-empty", ("skins", 0, "joints"), [], "error")]:
        add("skin-" + label, set_path(sk, path, v), exp)
    bad_j = cube_buffer(skin=True)
    bad_j = bad_j[:232] + bytes([7, 0, 0, 0] * 8) + bad_j[264:]
    d = gltf_doc(skin=True, uri=data_uri(bad_j))
    add("skin-joint-index-beyond", d, "error")
    mt = set_path(base, ("meshes", 0, "primitives", 0, "targets"), [{"POSITION": 0}])
    add("morph-weight-1", set_path(mt, ("meshes", 0, "weights"), [1]), "ok")
    add("morph-weight-1e38", set_path(mt, ("meshes", 0, "weights"), [1e38]), "error")
    add("morph-weights-3", set_path(mt, ("meshes", 0, "weights"), [1, 1, 1]), "either")
    for label, acc in [("vec2", 1), ("99", 99)]:
        t = set_path(base, ("meshes", 0, "primitives", 0, "targets"), [{"POSITION": acc}])
        add("morph-target-%s-weight-0" % label, t, "refuse-preferred")
        add("morph-target-%s" % label, set_path(t, ("meshes", 0, "weights"), [1]), "error")

    # Cameras.
    cam_doc = set_path(set_path(base, ("nodes",), [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 4]}]),
                       ("scenes", 0, "nodes"), [0, 1])
    for label, cam, exp in [("ok", {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}, "ok"),
                            ("yfov-0", {"type": "perspective", "perspective": {"yfov": 0, "znear": 0.01}}, "error"),
                            ("yfov-negative", {"type": "perspective", "perspective": {"yfov": -1, "znear": 0.01}}, "error"),
                            ("yfov-pi", {"type": "perspective", "perspective": {"yfov": 3.2, "znear": 0.01}}, "error"),
                            ("yfov-1e38", {"type": "perspective", "perspective": {"yfov": 1e38, "znear": 0.01}}, "error"),
                            ("znear-0", {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0}}, "either"),
                            ("orthographic", {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.01, "zfar": 100}}, "either"),
                            ("no-perspective", {"type": "perspective"}, "error")]:
        add("camera-" + label, set_path(cam_doc, ("cameras",), [cam]), exp)
    add("camera-99", set_path(cam_doc, ("nodes", 1, "camera"), 99), "error")

    # The JSON text itself.
    t = jtext(base)
    for label, text in [("empty", ""), ("truncated", t[: len(t) // 2]), ("array", "[]"), ("null", "null"),
                        ("deep-100000", "[" * 100000 + "]" * 100000),
                        ("deep-object-100000", '{"asset": {"version": "2.0"}, "x": ' + '{"a":' * 100000 + "1" + "}" * 100000 + "}")]:
        add("json-" + label, text, "error")

    # .glb containers.
    nb = del_path(gltf_doc(), ("buffers", 0, "uri"))
    good = glb_bytes(nb, buf)
    for label, data, exp in [
            ("magic", glb_bytes(nb, buf, magic=b"gLTF"), "error"), ("version-1", glb_bytes(nb, buf, version=1), "error"),
            ("version-3", glb_bytes(nb, buf, version=3), "error"), ("length-2^32-1", glb_bytes(nb, buf, length=0xFFFFFFFF), "error"),
            ("length-short", glb_bytes(nb, buf, length=20), "error"),
            ("json-length-beyond", glb_bytes(nb, buf, json_len=0x7FFFFFF0), "error"),
            ("json-kind", glb_bytes(nb, buf, json_kind=b"XXXX"), "error"),
            ("no-bin", glb_bytes(nb, None), "error"), ("bin-short", glb_bytes(nb, buf[:100]), "error"),
            ("bin-length-beyond", glb_bytes(nb, buf, bin_len=0xFFFFFFF0), "error"),
            ("truncated-12", good[:12], "error"), ("truncated-20", good[:20], "error"),
            ("truncated-mid-json", good[:60], "error"), ("truncated-mid-bin", good[:-40], "error"),
            ("empty", b"", "error"), ("json-garbage", glb_bytes(Raw("{{{{"), buf), "error"),
            ("gltf-1.0-binary", b"glTF" + struct.pack("<III", 1, 40, 8) + b"\0\0\0\0" + b"{}      ", "error")]:
        c.add("gltf", "glb-" + label, render("m.glb"), files={"m.glb": data}, expect=exp,
              names=("m.glb",) if exp == "error" else ())
    c.add("gltf", "glb-directory", render("m.glb"), files={"m.glb": Dir()}, expect="error", names=("m.glb",))
    c.add("gltf", "glb-fifo", render("m.glb"), files={"m.glb": Fifo()}, expect="error", names=("m.glb",))
    # A glTF inside a JSON scene.
    d = set_path(scene_dict(), ("meshes", 2), {"file": "m.gltf", "transform": {"translate": [-1.5, 0, 1.5]}})
    c.add("gltf", "in-json", render("scene.json"), files={"scene.json": jtext(d), "m.gltf": jtext(tex), "tex.png": TEX},
          expect="ok", check=sees_scene())


# ----------------------------------------------------------------------------------------------
# compare A.npy B.npy

def sidecar(kind="bitmask", samples=16, w=W, h=H, method="reference/cpu", **extra):
    d = {"format": "stsv light samples", "kind": kind, "samples": samples, "width": w, "height": h, "method": method}
    d.update(extra)
    return json.dumps(d)


def npy_surface(c: Cases):
    zeros = npy_bytes("|u1", (H, W, 2))
    flipped = bytearray(zeros)
    flipped[len(zeros) - W * H * 2 + (3 * W + 5) * 2 + 1] = 0b100  # pixel (5, 3), sample 10
    pair = {"a.npy": zeros, "a.npy.json": sidecar(), "b.npy": bytes(flipped), "b.npy.json": sidecar()}
    same = dict(pair, **{"b.npy": zeros})

    def add(name, files, exp="error", a=("a.npy", "b.npy"), extra=(), names=None, check=None, **kw):
        if names is None:
            names = ("a.npy",) if exp == "error" else ()
        c.add("npy", name, ["compare", *a, *extra], files=files, expect=exp, names=names, check=check,
              max_memory=None, **kw)

    none = stdout_has(r"differing samples: 0 of %d\b" % (W * H * 16), "identical files must differ in 0 samples")
    one = stdout_has(r"differing samples: 1 of %d\b" % (W * H * 16), "files one bit apart must differ in 1 sample")
    add("identical", same, "ok", check=none)
    add("one-bit", pair, "ok", check=one)
    add("same-path", same, "ok", a=("a.npy", "a.npy"), check=none)
    add("symlink-of-a", dict(same, **{"l.npy": Symlink("a.npy"), "l.npy.json": sidecar()}), "ok", a=("a.npy", "l.npy"), check=none)
    add("out-dir", pair, "ok", extra=("--out", "cmp"), check=one)
    c1 = bytearray(npy_bytes("|u1", (H, W, 16)))
    c2 = bytearray(c1)
    hdr = len(c1) - W * H * 16
    c1[hdr + 7] = 1
    c2[hdr + 7] = 3
    cnt = {"a.npy": bytes(c1), "a.npy.json": sidecar("counters"), "b.npy": bytes(c2), "b.npy.json": sidecar("counters")}
    add("counters-same-occlusion", cnt, "ok", check=none, desc="counts 1 and 3 are both occluded")
    tr = npy_bytes("<f2", (H, W, 16), data=struct.pack("<e", 1.0) * (H * W * 16))
    add("transmittance-identical", {"a.npy": tr, "a.npy.json": sidecar("transmittance"), "b.npy": tr,
                                    "b.npy.json": sidecar("transmittance")}, "ok", check=none)
    add("kinds-differ", dict(pair, **{"b.npy": npy_bytes("|u1", (H, W, 16)), "b.npy.json": sidecar("counters")}),
        names=("a.npy", "b.npy"))
    add("samples-differ", dict(pair, **{"b.npy": npy_bytes("|u1", (H, W, 4)), "b.npy.json": sidecar(samples=32)}),
        names=("a.npy", "b.npy"))
    add("width-differs", dict(pair, **{"b.npy": npy_bytes("|u1", (H, W + 1, 2)), "b.npy.json": sidecar(w=W + 1)}))
    add("height-differs", dict(pair, **{"b.npy": npy_bytes("|u1", (H + 1, W, 2)), "b.npy.json": sidecar(h=H + 1)}))
    add("sidecar-disagrees-with-shape", dict(pair, **{"b.npy": npy_bytes("|u1", (H, W + 1, 2))}), names=("b.npy",))
    add("sidecar-samples-disagree", dict(pair, **{"b.npy.json": sidecar(samples=64)}), names=("b.npy",))
    for label, descr, shape, item in [("u2-bitmask", "<u2", (H, W, 2), 2), ("f4-bitmask", "<f4", (H, W, 2), 4),
                                      ("bool", "|b1", (H, W, 2), 1), ("i8", "<i8", (H, W, 2), 8),
                                      ("big-endian-u2", ">u2", (H, W, 16), 2), ("unicode", "<U4", (H, W, 2), 16)]:
        add("dtype-" + label, dict(pair, **{"b.npy": npy_bytes(descr, shape, data=bytes(H * W * shape[2] * item))}),
            names=("b.npy",))
    add("dtype-object", dict(pair, **{"b.npy": npy_bytes("|O", (H, W, 2), data=b"")}), names=("b.npy",))
    add("fortran-order", dict(pair, **{"b.npy": npy_bytes("|u1", (H, W, 2), fortran=True)}), "either")
    add("truncated-data", dict(pair, **{"b.npy": zeros[:-100]}), names=("b.npy",))
    add("trailing-data", dict(pair, **{"b.npy": zeros + b"\0" * 100}), "either")
    add("header-length-huge", dict(pair, **{"b.npy": b"\x93NUMPY\x01\x00\xff\xff{'descr'"}), names=("b.npy",))
    add("header-not-dict", dict(pair, **{"b.npy": npy_bytes("|u1", (1,), header="[1, 2, 3]", data=b"")}), names=("b.npy",))
    add("header-garbage", dict(pair, **{"b.npy": npy_bytes("|u1", (1,), header="{'descr': '|u1', 'shape': (24, 32, 2", data=b"")}),
        names=("b.npy",))
    add("shape-negative", dict(pair, **{"b.npy": npy_bytes("|u1", (1,), header="{'descr': '|u1', 'fortran_order': False, 'shape': (-24, 32, 2), }", data=zeros[128:])}),
        names=("b.npy",))
    add("shape-2^40", dict(pair, **{"b.npy": npy_bytes("|u1", (1,), header="{'descr': '|u1', 'fortran_order': False, 'shape': (1099511627776, 32, 2), }", data=zeros[128:]),
                                    "b.npy.json": sidecar(h=1099511627776)}), names=("b.npy",))
    add("shape-overflow", dict(pair, **{"b.npy": npy_bytes("|u1", (1,), header="{'descr': '|u1', 'fortran_order': False, 'shape': (4294967296, 4294967296, 2), }", data=zeros[128:])}),
        names=("b.npy",))
    add("shape-zero", dict(pair, **{"b.npy": npy_bytes("|u1", (0, W, 2)), "b.npy.json": sidecar(h=0)}), names=("b.npy",))
    add("shape-1d", dict(pair, **{"b.npy": npy_bytes("|u1", (H * W * 2,))}), names=("b.npy",))
    add("shape-4d", dict(pair, **{"b.npy": npy_bytes("|u1", (1, H, W, 2))}), names=("b.npy",))
    add("version-2", dict(same, **{"b.npy": npy_bytes("|u1", (H, W, 2), version=2)}), "either")
    add("version-9", dict(pair, **{"b.npy": b"\x93NUMPY\x09\x00" + zeros[8:]}), names=("b.npy",))
    add("bad-magic", dict(pair, **{"b.npy": b"\x93NUMPX" + zeros[6:]}), names=("b.npy",))
    add("empty-file", dict(pair, **{"b.npy": b""}), names=("b.npy",))
    nojson = {"a.npy": zeros, "b.npy": bytes(flipped)}
    add("no-sidecar-u1", nojson, names=("--kind",))
    add("no-sidecar-kind-bitmask", nojson, "ok", extra=("--kind", "bitmask"), check=one)
    add("no-sidecar-kind-counters", nojson, "either", extra=("--kind", "counters"))
    add("no-sidecar-kind-bogus", nojson, extra=("--kind", "bogus"), names=("--kind",))
    add("no-sidecar-kind-empty", nojson, extra=("--kind", ""), names=("--kind",))
    u2 = npy_bytes("<u2", (H, W, 16))
    add("no-sidecar-u2", {"a.npy": u2, "b.npy": u2}, "ok", check=none)
    add("no-sidecar-f2", {"a.npy": tr, "b.npy": tr}, "ok", check=none)
    add("samples-option-mismatch", pair, extra=("--samples", "32"), names=("--samples",))
    add("samples-option-match", pair, "ok", extra=("--samples", "16"), check=one)
    for label, side, exp in [("malformed", "{", "error"), ("kind-bogus", sidecar("bogus"), "error"),
                             ("samples-negative", sidecar(samples=-1), "error"), ("samples-0", sidecar(samples=0), "error"),
                             ("samples-1e9", sidecar(samples=1000000000), "error"), ("samples-string", sidecar(samples="16"), "error"),
                             ("width-1e20", sidecar(w=1e20), "error"), ("format-other", sidecar(format="other"), "error"),
                             ("array", "[]", "error"), ("deep", "[" * 100000 + "]" * 100000, "error")]:
        add("sidecar-" + label, dict(pair, **{"b.npy.json": side}), exp, names=("b.npy",))
    add("sidecar-directory", dict(pair, **{"b.npy.json": Dir()}), names=("b.npy",))
    add("sidecar-fifo", dict(pair, **{"b.npy.json": Fifo()}), names=("b.npy",))
    add("a-directory", dict(pair, **{"a.npy": Dir()}))
    add("a-fifo", dict(pair, **{"a.npy": Fifo()}))
    add("a-dev-zero", dict(pair, **{"a.npy": Symlink("/dev/zero")}))
    add("a-missing", {"b.npy": zeros, "b.npy.json": sidecar()})
    vis = npy_bytes("<f4", (H, W), data=struct.pack("<f", 0.5) * (H * W))
    vside = json.dumps({"format": "stsv visibility", "samples": 16, "width": W, "height": H, "lights": 1, "method": "pcss/cpu"})
    vpair = {"a.npy": vis, "a.npy.json": vside, "b.npy": vis, "b.npy.json": vside}
    add("visibility-identical", vpair, "ok", check=stdout_has(r"(?i)rmse\D*0(\.0+)?\b", "identical images must have RMSE 0"))
    add("visibility-shape-differs", dict(vpair, **{"b.npy": npy_bytes("<f4", (H, W + 1))}), names=("b.npy",))
    nan = npy_bytes("<f4", (H, W), data=struct.pack("<f", float("nan")) * (H * W))
    add("visibility-nan", dict(vpair, **{"b.npy": nan}), "either")
    add("visibility-vs-bitmask", dict(vpair, **{"b.npy": zeros, "b.npy.json": sidecar()}), names=("b.npy",))
    add("npy-vs-exr", {"a.npy": vis, "a.npy.json": vside, "b.exr": b"\x76\x2f\x31\x01" + b"\0" * 100}, a=("a.npy", "b.exr"),
        names=("b.exr",))
    add("exr-garbage", {"a.exr": b"\x76\x2f\x31\x01" + b"\0" * 100, "b.exr": b"\x76\x2f\x31\x01" + b"\0" * 100},
        a=("a.exr", "b.exr"), names=("a.exr",))
    for opt, val in [("--json", "t.json"), ("--report", "rep"), ("--converged", "2"), ("--sheet", "s.png")]:
        add("two-files-with-" + opt.strip("-"), pair, extra=(opt, val), names=(opt,))
    add("out-is-file", dict(pair, **{"cmp": "x"}), extra=("--out", "cmp"), names=("cmp",))
    add("out-is-fifo", dict(pair, **{"cmp": Fifo()}), extra=("--out", "cmp"), names=("cmp",))
    add("three-inputs", dict(pair, **{"c.npy": zeros}), a=("a.npy", "b.npy", "c.npy"), names=())
    big = npy_bytes("|u1", (1024, 1024, 32))
    add("big-1024-256-samples", {"a.npy": big, "a.npy.json": sidecar(samples=256, w=1024, h=1024),
                                 "b.npy": big, "b.npy.json": sidecar(samples=256, w=1024, h=1024)}, "ok",
        check=stdout_has(r"differing samples: 0 of", "identical files must differ in 0 samples"))


# ----------------------------------------------------------------------------------------------
# Command-line values

INT_VALUES = ["", "-1", "0", "1", "abc", "1.5", "1e3", "0x10", "010", " 16", "16 ", "+16", "nan",
              "4294967295", "4294967296", "18446744073709551616", "99999999999999999999999999"]
FLOAT_VALUES = ["", "-1", "0", "0.5", "1", "2", "nan", "inf", "-inf", "1e38", "1e-38", "-0", "abc",
                "1e400", "0x1p-2"]


def int_expect(value: str, valid) -> str:
    if re.fullmatch(r"\d+", value):
        return "ok" if valid(int(value)) else "error"
    if value.strip() != value or value.startswith("+") or value == "1e3":
        return "either"
    return "error"


def float_expect(value: str, lo=None, hi=None) -> str:
    if value.startswith("0x"):
        return "refuse-preferred"  # a C hexadecimal float: strtod reads it
    try:
        x = float(value)
    except ValueError:
        return "error"
    if x != x or x in (float("inf"), float("-inf")):
        return "error"
    if value.startswith("0x"):
        return "refuse-preferred"
    if (lo is not None and x < lo) or (hi is not None and x > hi):
        return "error"
    return "either"


PRESETS_OK = json.dumps({"tiny": {"description": "probe", "scene": "fence", "size": "32x24", "samples": "16",
                                  "methods": "stsv", "backends": "cpu", "repeat": 1, "warmup": 0}})


def cli_surface(c: Cases):
    base_r = ["render", "fence", *SIZE, "--backend", "cpu", "-o", "out.png"]
    base_c = ["compare", "fence", *SIZE, "--methods", "stsv/cpu", "--backend", "cpu"]
    base_b = ["bench", "fence", "--size", "32x24", "--samples", "16", "--methods", "stsv", "--backends", "cpu",
              "--repeat", "1", "--warmup", "0"]
    base_i = ["info", "fence"]
    bases = {"render": base_r, "compare": base_c, "bench": base_b, "info": base_i}

    def with_opt(base, opt, value):
        a = list(base)
        if opt in a:
            i = a.index(opt)
            a[i + 1] = value
        else:
            a += [opt, value]
        return a

    c.add("cli", "render-base", base_r, expect="ok", check=sees_scene())
    c.add("cli", "compare-base", base_c, expect="ok")
    c.add("cli", "bench-base", base_b, expect="ok")
    c.add("cli", "info-base", base_i, expect="ok")
    c.add("cli", "info-plain", ["info"], expect="ok")
    c.add("cli", "info-json", ["info", "--json"], expect="ok",
          check=lambda ctx: None if json.loads(ctx.stdout) else "empty JSON")
    c.add("cli", "info-scene-json", ["info", "fence", "--json"], expect="ok",
          check=lambda ctx: None if "memory" in json.loads(ctx.stdout) else "no memory in info --json")
    c.add("cli", "info-methods", ["info", "--methods"], expect="ok")
    c.add("cli", "info-markdown", ["info", "--markdown"], expect="ok")
    c.add("cli", "version", ["--version"], expect="ok", max_memory=None)
    c.add("cli", "no-arguments", [], expect="either", max_memory=None, outputs=None)
    c.add("cli", "unknown-command", ["paint", "fence"], expect="error", max_memory=None, names=("paint",))
    c.add("cli", "unknown-option", base_r + ["--bogus"], expect="error", names=("--bogus",))
    c.add("cli", "option-missing-value", base_r + ["--seed"], expect="error", names=("--seed",))
    c.add("cli", "option-twice", base_r + ["--seed", "1", "--seed", "2"], expect="either")
    c.add("cli", "render-no-scene", ["render"], expect="error", names=("scene",))
    c.add("cli", "render-two-scenes", ["render", "fence", "foliage", *SIZE], expect="error")
    c.add("cli", "scene-empty-name", ["render", "", *SIZE, "--backend", "cpu"], expect="error", names=("scene",))
    c.add("cli", "scene-unknown", ["render", "bogus", *SIZE, "--backend", "cpu"], expect="error", names=("bogus",))
    c.add("cli", "scene-control-chars", ["render", "\x1b[31mred\n.json", *SIZE, "--backend", "cpu"], expect="error",
          names=("\\x1b",))
    c.add("cli", "scene-invalid-utf8", ["render", os.fsdecode(b"\xff\xfe.json"), *SIZE, "--backend", "cpu"],
          expect="error", names=("\\xff",))
    c.add("cli", "scene-directory", ["render", "d.json", *SIZE, "--backend", "cpu"], files={"d.json": Dir()},
          expect="error", names=("d.json",))
    c.add("cli", "scene-fifo", ["render", "f.json", *SIZE, "--backend", "cpu"], files={"f.json": Fifo()},
          expect="error", names=("f.json",))
    c.add("cli", "scene-dev-zero", ["render", "z.json", *SIZE, "--backend", "cpu"], files={"z.json": Symlink("/dev/zero")},
          expect="error", names=("z.json",))
    c.add("cli", "scene-dev-stdin", ["render", "/dev/stdin", *SIZE, "--backend", "cpu"], expect="error",
          names=("/dev/stdin",))

    int_opts = [
        ("--samples", lambda n: n in (16, 32, 64, 128, 256), ["render", "compare", "info"]),
        ("--seed", lambda n: 0 <= n <= 4294967295, ["render", "compare", "bench", "info"]),
        ("--interleave", lambda n: 1 <= n <= 8, ["render", "compare", "bench", "info"]),
        ("--supersample", lambda n: 1 <= n <= 4, ["render", "compare", "bench", "info"]),
    ]
    for opt, valid, cmds in int_opts:
        for cmd in cmds:
            values = INT_VALUES if cmd == "render" else ["", "-1", "0", "abc", "1.5", "4294967296", "99999999999999999999999999"]
            for v in values:
                exp = int_expect(v, valid)
                if opt == "--supersample" and v == "4294967295":
                    exp = "error"
                c.add("cli", "%s%s=%s" % (cmd, opt, v), with_opt(bases[cmd], opt, v), expect=exp,
                      names=(opt,) if exp == "error" else (), check=sees_scene() if cmd == "render" and exp == "ok" else None)
    for opt, valid in [("--repeat", lambda n: n >= 1), ("--warmup", lambda n: n >= 0)]:
        for v in INT_VALUES:
            exp = int_expect(v, valid)
            if v in ("4294967295", "4294967296") or len(v) > 12:
                exp = "error" if exp == "error" or not v.isdigit() or int(v) > 4294967295 else "either"
                if v == "4294967295":
                    exp = "either"
            timeout = DEFAULT_TIMEOUT
            c.add("cli", "bench%s=%s" % (opt, v), with_opt(base_b, opt, v), expect=exp,
                  names=(opt,) if exp == "error" else (), timeout=timeout,
                  desc="a large repeat count runs until the timeout: a hang here is the request, not a bug"
                  if v.isdigit() and int(v) > 1000 else "")
    for v in ["", "-1", "0", "1", "abc", "1.5", "4294967296", "99999999999999999999999999"]:
        exp = int_expect(v, lambda n: n >= 1)
        if exp == "ok" and int(v) > 4096:
            exp = "either"  # a range the user guide does not give
        c.add("cli", "compare--converged=%s" % v, with_opt(base_c, "--converged", v), expect=exp if v != "0" else "either",
              names=("--converged",) if exp == "error" else ())
    for v in FLOAT_VALUES:
        exp = float_expect(v, 0.0, None)
        if v in ("1e38", "2"):
            exp = "either"
        c.add("cli", "render--ambient=%s" % v, with_opt(base_r, "--ambient", v), expect=exp,
              names=("--ambient",) if exp == "error" else ())
        exp = float_expect(v, 0.0, None)
        if v in ("0", "-0"):
            exp = "refuse-preferred"
        c.add("cli", "compare--heat-scale=%s" % v, with_opt(base_c, "--heat-scale", v), expect=exp,
              names=("--heat-scale",) if exp == "error" else ())
    for v in ["", "0x0", "1x1", "32x24", "16384x1", "16385x1", "1x16385", "-32x24", "32x-24", "32x", "x24", "32",
              "32X24", "32x24x2", "32.5x24", "4294967328x24", "18446744073709551648x24", " 32x24", "0x24", "axb",
              "32*24", "16384x16384", "032x024"]:
        exp = "error"
        if v in ("1x1", "32x24", "16384x1"):
            exp = "ok"
        elif v in ("32X24", " 32x24", "032x024"):
            exp = "either"
        for cmd in ("render", "info", "compare", "bench"):
            if cmd != "render" and v not in ("", "0x0", "16385x1", "-32x24", "4294967328x24", "16384x16384", "axb"):
                continue
            e = exp
            if cmd == "info" and v == "16384x16384":
                e = "either"  # info only reports the frame's memory against the limit
            c.add("cli", "%s--size=%s" % (cmd, v), with_opt(bases[cmd], "--size", v), expect=e,
                  names=("--size",) if e == "error" and v != "16384x16384" else (),
                  check=None)
    enum_opts = [("--pattern", ["", "bogus", "POISSON", "poisson ", "lowdisc", "uniform", "stratified"], ("lowdisc", "uniform", "stratified")),
                 ("--buffer", ["", "bogus", "BITMASK", "counters", "transmittance"], ("counters", "transmittance")),
                 ("--method", ["", "bogus", "STSV", "stsv ", "reference", "pw", "dcs", "pw+stsv", "dcs+stsv",
                               "stsv+pw", "stsv,pw"], ("reference", "pw", "dcs", "pw+stsv", "dcs+stsv")),
                 ("--backend", ["", "bogus", "CPU", "gpu"], ()),
                 ("--extrusion", ["", "bogus", "HULL"], ())]
    for opt, values, good in enum_opts:
        for v in values:
            exp = "ok" if v in good else ("either" if v.upper() == v and v.strip() and v != "" and v.isalpha() else "error")
            c.add("cli", "render%s=%s" % (opt, v), with_opt(base_r, opt, v), expect=exp,
                  names=((v,) if v else (opt,)) if exp == "error" else (), check=sees_scene() if exp == "ok" else None)
    for v in ["", "bogus", "stsv,", ",stsv", "stsv,,stsv/cpu", "stsv/gpu", "stsv/cpu,stsv/cpu", "reference/vulkan",
              "STSV/cpu", "stsv/cpu/cpu"]:
        exp = "either" if v in ("stsv/cpu,stsv/cpu", "STSV/cpu") else "error"
        if v in ("stsv,", ",stsv", "stsv,,stsv/cpu"):
            exp = "refuse-preferred"
        c.add("cli", "compare--methods=%s" % v, with_opt(base_c, "--methods", v), expect=exp,
              names=("--methods",) if exp == "error" and v == "" else ())
    allm = ",".join(m + "/cpu" for m in ["stsv", "pw", "dcs", "pw+stsv", "dcs+stsv", "pcf", "pcss", "vsm", "esm", "evsm",
                                          "msm", "csm", "peel", "avsm", "vpcss"])
    # At the default sm_size=2048, csm's frame needs about 1.5 GiB (its 2M planes of summed-area
    # tables), above --max-memory 1G: every method fits at sm_size=512, and csm alone is refused.
    c.add("cli", "compare-every-method-cpu", with_opt(base_c, "--methods", allm) + ["--param", "sm_size=512"],
          expect="ok", timeout=180, budget_mb=BUDGET_LIMIT)
    c.add("cli", "compare-csm-default-above-max-memory", with_opt(base_c, "--methods", "csm/cpu"), expect="error",
          names=("memory",), timeout=180, budget_mb=BUDGET_LIMIT)
    for v in ["", "bogus", "stsv/cpu", "pcss/cpu", "reference/vulkan", "reference/cpu"]:
        exp = "ok" if v in ("stsv/cpu", "pcss/cpu", "reference/cpu") else "error"
        c.add("cli", "compare--against=%s" % v, with_opt(base_c, "--against", v), expect=exp,
              names=("--against",) if exp == "error" and v == "" else ())
    c.add("cli", "compare-kind-with-scene", base_c + ["--kind", "bitmask"], expect="error", names=("--kind",))
    for v in ["", "16,", ",16", "16,,32", "16,abc", "17", "16,32", "16 32", "16,16"]:
        exp = "ok" if v in ("16,32",) else ("either" if v in ("16,16",) else "error")
        if v in ("16,", ",16", "16,,32"):
            exp = "refuse-preferred"
        c.add("cli", "bench--samples=%s" % v, with_opt(base_b, "--samples", v), expect=exp,
              names=("--samples",) if exp == "error" else ())
    for v in ["", "bogus", "stsv,", "stsv,reference", "stsv,stsv"]:
        exp = "ok" if v == "stsv,reference" else ("either" if v == "stsv,stsv" else "error")
        if v == "stsv,":
            exp = "refuse-preferred"
        c.add("cli", "bench--methods=%s" % v, with_opt(base_b, "--methods", v), expect=exp)
    for v in ["", "bogus", "cpu,cpu", "CPU"]:
        exp = "either" if v in ("cpu,cpu", "CPU") else "error"
        c.add("cli", "bench--backends=%s" % v, with_opt(base_b, "--backends", v), expect=exp)
    for v in ["", "bogus", "count=", "count=1,2", "repeat=1,2", "repeat=1,,2", "scene=fence,bogus", "scene=",
              "repeat=0", "light_size=nan", "repeat", "=1", "scene=fence,foliage", "repeat=99999"]:
        exp = "ok" if v in ("repeat=1,2", "scene=fence,foliage") else "error"
        if v == "repeat=1,,2":
            exp = "refuse-preferred"
        c.add("cli", "bench--vary=%s" % v, base_b + ["--vary", v], expect=exp, timeout=120)
    for v in ["", "bogus"]:
        c.add("cli", "bench--preset=%s" % v, ["bench", "--preset", v, "--repeat", "1"], expect="error",
              names=("--preset",) if v == "" else ("bogus",))
    c.add("cli", "bench-list-presets", ["bench", "--list-presets"], expect="ok")
    c.add("cli", "bench-check", with_opt(base_b, "--methods", "stsv,reference") + ["--check"], expect="ok")
    c.add("cli", "bench-check-without-reference", base_b + ["--check"], expect="either")
    c.add("cli", "bench-no-scene", ["bench", "--size", "32x24", "--repeat", "1"], expect="error")
    presets_ok = PRESETS_OK
    for label, f, exp in [("missing", {}, "error"), ("directory", {"p.json": Dir()}, "error"),
                          ("fifo", {"p.json": Fifo()}, "error"), ("malformed", {"p.json": "{"}, "error"),
                          ("empty-object", {"p.json": "{}"}, "error"), ("array", {"p.json": "[]"}, "error"),
                          ("deep", {"p.json": "[" * 100000 + "]" * 100000}, "error"),
                          ("dev-zero", {"p.json": Symlink("/dev/zero")}, "error"),
                          ("valid", {"p.json": presets_ok}, "ok"),
                          ("samples-array", {"p.json": presets_ok.replace('"16"', '[16]')}, "error"),
                          ("repeat-huge", {"p.json": presets_ok.replace('"repeat": 1', '"repeat": 1e30')}, "error"),
                          ("size-huge", {"p.json": presets_ok.replace('"32x24"', '"16384x16384"')}, "error")]:
        c.add("cli", "bench--presets=" + label, ["bench", "--presets", "p.json", "--preset", "tiny"], files=f,
              expect=exp, names=("p.json",) if exp == "error" and label != "size-huge" else ())
    # Options that take JSON.
    for opt in ("--camera", "--light", "--add-light"):
        values = [("empty", "", "error"), ("empty-object", "{}", "error"), ("open-brace", "{", "error"),
                  ("null", "null", "error"), ("array", "[]", "error"),
                  ("deep", "[" * 60000 + "]" * 60000, "error"),  # one argument holds at most 128 KiB
                  ("unknown-key", '{"bogus": 1}', "error")]
        if opt == "--camera":
            values += [("no-target", '{"eye": [0, 1, 5]}', "error"),
                       ("eye-is-target", '{"eye": [0, 1, 5], "target": [0, 1, 5]}', "error"),
                       ("nan", '{"eye": [NaN, 1, 5], "target": [0, 0, 0]}', "error"),
                       ("fov-0", '{"eye": [0, 1, 5], "target": [0, 0, 0], "fovY": 0}', "error"),
                       ("fov-180", '{"eye": [0, 1, 5], "target": [0, 0, 0], "fovY": 180}', "error"),
                       ("up-along-view", '{"eye": [0, 5, 0], "target": [0, 0, 0], "up": [0, 1, 0]}', "error"),
                       ("eye-1e38", '{"eye": [1e38, 1, 5], "target": [0, 0, 0]}', "either"),
                       ("ok", '{"eye": [0, 3, 8], "target": [0, 0, 0], "fovY": 40}', "ok")]
        else:
            values += [("type-bogus", '{"type": "bogus"}', "error"),
                       ("normal-zero", '{"type": "disk", "position": [0, 4, 0], "normal": [0, 0, 0], "radius": 0.5, "radiance": 40}', "error"),
                       ("radius-0", '{"type": "disk", "position": [0, 4, 0], "normal": [0, -1, 0], "radius": 0, "radiance": 40}', "error"),
                       ("radius-1e38", '{"type": "sphere", "position": [0, 4, 0], "radius": 1e38, "radiance": 40}', "either"),
                       ("angular-90", '{"type": "directional", "direction": [0, 1, 0], "angularRadius": 90, "radiance": 5}', "error"),
                       ("radiance-nan", '{"type": "sphere", "position": [0, 4, 0], "radius": 0.5, "radiance": NaN}', "error"),
                       ("ok", '{"type": "sphere", "position": [0, 4, 0], "radius": 0.5, "radiance": 40}', "ok")]
        for label, v, exp in values:
            c.add("cli", "render%s=%s" % (opt, label), base_r + [opt, v], expect=exp,
                  names=(opt,) if exp == "error" else (), check=sees_scene() if exp == "ok" else None)
    # CLI11 reads a vector option's value in brackets as a list: every repeatable option.
    deep = "[" * 60000 + "]" * 60000
    c.add("cli", "render--set=deep-brackets", base_r + ["--set", deep], expect="error", names=("--set",))
    c.add("cli", "render--param=deep-brackets", base_r + ["--method", "pcss", "--param", deep], expect="error",
          names=("--param",))
    c.add("cli", "render--set=bracket-list", base_r + ["--set", "[repeat=2,texture_size=16]"], expect="refuse-preferred",
          desc="CLI11 splits a bracketed value into two knobs")
    many = []
    for i in range(100):
        many += ["--add-light", '{"type": "sphere", "position": [%d, 4, 0], "radius": 0.1, "radiance": 1}' % (i % 10)]
    c.add("cli", "render--add-light-x100", base_r + many, expect="either", check=sees_scene(), timeout=120)
    # --max-memory.
    for v, exp in [("", "error"), ("0", "error"), ("1", "error"), ("1K", "error"), ("64M", "either"), ("1G", "ok"),
                   ("1T", "ok"), ("1E", "either"), ("99999999999999999999G", "error"), ("-1G", "error"),
                   ("1.5G", "either"), ("abc", "error"), ("1g", "either"), ("1Gi", "either"), ("1GB", "either"),
                   ("G", "error"), ("1 G", "either"), ("16E", "either"), ("17179869184G", "error")]:
        for cmd in ("render", "info"):
            if cmd == "info" and v not in ("", "1", "abc", "-1G", "99999999999999999999G"):
                continue
            c.add("cli", "%s--max-memory=%s" % (cmd, v), bases[cmd] + ["--max-memory", v], expect=exp,
                  names=("--max-memory",) if exp == "error" and v not in ("1", "1K", "0") else (),
                  check=sees_scene() if exp == "ok" and cmd == "render" else None)
    c.add("cli", "render--max-memory-1K-fence", base_r + ["--max-memory", "1K"], expect="error",
          names=("--max-memory",))


def knob_range(help_text):
    m = re.search(r"([\[(])\s*([-+0-9.e]+)\s*,\s*([-+0-9.e]+)\s*([\])])", help_text)
    if not m:
        return None
    return float(m.group(2)), float(m.group(3)), m.group(1) == "(", m.group(4) == ")"


def fmt(x: float) -> str:
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def knobs_surface(c: Cases, info: dict):
    for scene in info.get("scenes", []):
        name = scene["name"]
        for knob in scene.get("knobs", []):
            k, default, help_text = knob["name"], knob.get("default", ""), knob.get("help", "")
            rng = knob_range(help_text)
            integer = "." not in default and "e" not in default.lower() and (
                rng is None or (rng[0] == int(rng[0]) and rng[1] == int(rng[1])))
            values = []
            if rng:
                lo, hi, lo_open, hi_open = rng
                values += [(fmt(lo), "error" if lo_open else "either"), (fmt(hi), "error" if hi_open else "either")]
                below = lo - (1 if integer else max(abs(lo) * 0.5, 1e-6))
                above = hi + (1 if integer else max(abs(hi) * 0.5, 1e-6))
                values += [(fmt(below), "error"), (fmt(above), "error"), (fmt(hi * 1000 + 1000), "error")]
                if integer:
                    values.append((fmt(lo) + ".5", "either"))
            if "unsigned 64-bit" in help_text:
                values += [("0", "either"), ("18446744073709551615", "either"), ("18446744073709551616", "error"),
                           ("-1", "error")]
            values += [("abc", "error"), ("", "error"), ("nan", "error"), ("inf", "error"), ("1e400", "error"),
                       ("-0", "either"), (default, "ok")]
            seen = set()
            for v, exp in values:
                if v in seen:
                    continue
                seen.add(v)
                # fence-mesh's defaults make 2.4 M triangles (6 GB): the other knob keeps it small
                small = []
                if name == "fence-mesh":
                    small = ["--set", "repeat=1"] if k == "texture_size" else ["--set", "texture_size=16"]
                c.add("knobs", "%s.%s=%s" % (name, k, v),
                      ["render", name, *SIZE, "--backend", "cpu", "-o", "out.png", *small, "--set", "%s=%s" % (k, v)],
                      expect=exp, names=(k,) if exp == "error" else (), budget_mb=BUDGET_LIMIT, timeout=120,
                      check=sees_scene() if exp == "ok" else None)
    r = ["render", "fence", *SIZE, "--backend", "cpu", "-o", "out.png"]
    for label, sets, exp in [("no-equals", ["repeat"], "error"), ("empty-key", ["=5"], "error"),
                             ("unknown", ["bogus=1"], "error"), ("other-scenes-knob", ["count=1"], "error"),
                             ("twice", ["repeat=2", "repeat=3"], "either"), ("two-equals", ["repeat=1=2"], "error"),
                             ("space", ["repeat = 2"], "error"), ("empty", [""], "error"),
                             ("combined-limit", ["repeat=4096", "texture_size=8192"], "error")]:
        a = list(r)
        for s in sets:
            a += ["--set", s]
        c.add("knobs", "fence-" + label, a, expect=exp, budget_mb=BUDGET_LIMIT)
    c.add("knobs", "file-scene-with-knob", ["render", "scene.json", *SIZE, "--backend", "cpu", "-o", "out.png",
                                            "--set", "count=1"], files=scene_files(), expect="error", names=("count",))


def params_surface(c: Cases, info: dict):
    seen_names = set()
    for m in info.get("methods", []):
        method = m["name"]
        backend = "cpu" if "cpu" in m.get("backends", []) else m["backends"][0]
        base = ["render", "fence", *SIZE, "--backend", backend, "--method", method, "-o", "out.png"]
        for p in m.get("parameters", []):
            name, lo, hi, integer = p["name"], p["min"], p["max"], p.get("integer", False)
            step = 1 if integer else max(abs(hi) * 0.5, 1e-6)
            cases = [(fmt(hi), "either"), (fmt(hi + step), "error")]
            if name not in seen_names:
                seen_names.add(name)
                cases += [(fmt(lo), "either"), (fmt(lo - (1 if integer else max(abs(lo) * 0.5, 1e-6))), "error"),
                          ("abc", "error"), ("", "error"), ("nan", "error"), ("inf", "error"),
                          (fmt(hi * 1e6 + 1e6), "error")]
                if integer:
                    cases.append((fmt(lo) + ".5", "error"))
            for v, exp in cases:
                c.add("params", "%s.%s=%s" % (method, name, v), base + ["--param", "%s=%s" % (name, v)], expect=exp,
                      names=(name,) if exp == "error" else (), budget_mb=BUDGET_LIMIT, timeout=180,
                      check=sees_scene() if exp != "error" else None)
    base = ["render", "fence", *SIZE, "--backend", "cpu", "-o", "out.png"]
    c.add("params", "reference-any", base + ["--method", "reference", "--param", "sm_size=512"], expect="error",
          names=("sm_size",))
    c.add("params", "pcss-unknown", base + ["--method", "pcss", "--param", "bogus=1"], expect="error", names=("bogus",))
    c.add("params", "pcss-no-equals", base + ["--method", "pcss", "--param", "sm_size"], expect="error", names=("sm_size",))
    c.add("params", "pcss-twice", base + ["--method", "pcss", "--param", "sm_size=512", "--param", "sm_size=256"],
          expect="either")
    c.add("params", "pcss-empty", base + ["--method", "pcss", "--param", ""], expect="error", names=("--param",))
    # Middle map sizes the estimate lets through: the peak must stay within --max-memory.
    for method, param in [("pcf", "sm_size=4096"), ("pcss", "sm_size=4096"), ("vsm", "sm_size=4096"),
                          ("esm", "sm_size=4096"), ("evsm", "sm_size=4096"), ("msm", "sm_size=4096"),
                          ("csm", "sm_size=4096"), ("csm", "sm_size=1024"), ("peel", "peel_size=1024"),
                          ("avsm", "avsm_size=4096"), ("vpcss", "avsm_size=4096")]:
        c.add("params", "%s-middle-%s" % (method, param), base + ["--method", method, "--param", param], expect="either",
              budget_mb=BUDGET_LIMIT, timeout=180, desc="refused by the estimate, or run within --max-memory 1G")
    # Several large maps at once: the memory estimate holds them together.
    c.add("params", "avsm-max-size-and-nodes", base + ["--method", "avsm", "--param", "avsm_size=8192", "--param",
                                                      "avsm_nodes=16"], expect="error", budget_mb=BUDGET_LIMIT,
          timeout=180, names=("--max-memory",))
    c.add("params", "peel-max-size-and-bins", base + ["--method", "peel", "--param", "peel_size=4096", "--param",
                                                     "peel_bins=32"], expect="either", budget_mb=BUDGET_LIMIT, timeout=180)
    c.add("params", "csm-max", base + ["--method", "csm", "--param", "sm_size=8192", "--param", "csm_terms=16"],
          expect="either", budget_mb=BUDGET_LIMIT, timeout=180)
    c.add("params", "evsm-max-sat", base + ["--method", "evsm", "--param", "sm_size=8192", "--param", "fm_mip=0"],
          expect="either", budget_mb=BUDGET_LIMIT, timeout=180)


# ----------------------------------------------------------------------------------------------
# Output paths

def outputs_surface(c: Cases):
    sf = scene_files()
    r = ["render", "scene.json", *SIZE, "--backend", "cpu"]

    def add(name, extra, files=None, exp="error", names=(), check=None, **kw):
        f = dict(sf)
        f.update(files or {})
        c.add("outputs", name, r + list(extra), files=f, expect=exp, names=names, check=check, **kw)

    add("o-directory", ["-o", "d.png"], {"d.png": Dir()}, names=("d.png",))
    add("o-fifo", ["-o", "f.png"], {"f.png": Fifo()}, names=("f.png",))
    add("o-dev-null", ["-o", "/dev/null"], names=("/dev/null",))
    add("o-dev-full-link", ["-o", "full.png"], {"full.png": Symlink("/dev/full")}, names=("full.png",))
    add("o-missing-dir", ["-o", "missing/out.png"], exp="either")
    add("o-jpg", ["-o", "out.jpg"], names=("out.jpg",))
    add("o-no-ext", ["-o", "out"], names=("out",))
    add("o-upper-ext", ["-o", "out.PNG"], exp="either")
    add("o-empty", ["-o", ""], names=("-o",))
    add("o-dot", ["-o", "."], names=("-o",))
    add("o-trailing-slash", ["-o", "out.png/"], names=("out.png",))
    add("o-scene", ["-o", "scene.json"], names=("scene.json",))
    add("o-texture", ["-o", "tex.png"], names=("tex.png",))
    add("o-texture-spelled", ["-o", "./sub/../tex.png"], {"sub": Dir()}, names=("tex.png",))
    add("o-texture-symlink", ["-o", "link.png"], {"link.png": Symlink("tex.png")}, names=("link.png",))
    add("o-texture-hardlink", ["-o", "hard.png"], {"hard.png": Hardlink("tex.png")}, names=("hard.png",))
    add("o-proc", ["-o", "/proc/out.png"], names=("/proc/out.png",))
    add("o-long-name", ["-o", "x" * 300 + ".png"], names=("x" * 20,))
    add("o-newline-name", ["-o", "a\nb.png"], exp="ok",
        check=lambda ctx: "raw newline in a printed path" if "a\nb.png" in ctx.stderr else None)
    add("o-fsize-limit", ["-o", "out.png"], limits=["--fsize=100"], names=("out.png",),
        desc="a file size limit: the write must fail with an error, not SIGXFSZ")
    add("o-and-visibility-same", ["-o", "out.png", "--visibility", "out.png"], names=("out.png",))
    add("o-and-visibility-spelled", ["-o", "out.png", "--visibility", "./out.png"], names=("out.png",))
    add("visibility-sidecar-vs-stats", ["--visibility", "v.npy", "--stats", "v.npy.json"], names=("v.npy.json",))
    two = scene_dict()
    two["lights"].append(dict(two["lights"][0], position=[2, 3, 0]))
    two_files = {"scene.json": jtext(two), "tex.png": TEX}
    c.add("outputs", "dump-ls-light1-vs-visibility", r + ["--dump-ls", "ls.npy", "--visibility", "ls_light1.npy"],
          files=two_files, expect="error", names=("ls_light1.npy",))
    c.add("outputs", "dump-ls-two-lights", r + ["--dump-ls", "ls.npy", "--method", "reference"], files=two_files,
          expect="ok", required=("ls.npy", "ls.npy.json", "ls_light1.npy", "ls_light1.npy.json"))
    c.add("outputs", "dump-ls-sidecar-vs-stats", r + ["--dump-ls", "ls.npy", "--stats", "ls_light1.npy.json"],
          files=two_files, expect="error", names=("ls_light1.npy.json",))
    add("dump-ls-same-as-visibility", ["--dump-ls", "a.npy", "--visibility", "a.npy"], names=("a.npy",))
    add("dump-ls-visibility-method", ["--dump-ls", "a.npy", "--method", "pcss"], names=("--dump-ls",))
    add("shadow-map-stsv", ["--shadow-map", "m.npy", "--method", "stsv"], names=("--shadow-map",))
    add("shadow-map-peel", ["--shadow-map", "m.npy", "--method", "peel"], names=("--shadow-map",))
    add("shadow-map-pcf", ["--shadow-map", "m.npy", "--method", "pcf", "--param", "sm_size=256", "-o", "out.png"],
        exp="ok", check=lambda ctx: None if read_npy(ctx.dir / "m.npy")[0]["descr"] == "<f4" else "shadow map not float32")
    add("shadow-map-alone", ["--shadow-map", "m.npy", "--method", "pcf", "--param", "sm_size=256"], exp="ok",
        desc="SCENE.png is written as well: --shadow-map is not one of the options that replace it")
    add("stats", ["--stats", "s.json", "-o", "out.png"], exp="ok",
        check=lambda ctx: None if "options" in json.loads((ctx.dir / "s.json").read_text()) else "stats without options")
    add("stats-dev-stdout", ["--stats", "/dev/stdout"], exp="either")
    add("stats-ext", ["--stats", "s.txt"], names=("s.txt",))
    add("visibility-exr", ["--visibility", "v.exr"], exp="ok")
    add("default-output", [], exp="ok", required=("scene.png",), check=sees_scene("scene.png"))
    sub = {"sub/scene2.json": jtext(scene_dict()), "sub/tex.png": TEX}
    c.add("outputs", "default-output-subdir", ["render", "sub/scene2.json", *SIZE, "--backend", "cpu"], files=sub,
          expect="ok", required=("scene2.png",), check=sees_scene("scene2.png"))
    d = set_path(scene_dict(), ("materials", 2, "alphaTexture"), "scene.png")
    c.add("outputs", "default-output-is-texture", r, files={"scene.json": jtext(d), "scene.png": TEX}, expect="error",
          names=("scene.png",))
    c.add("outputs", "o-is-obj-input", ["render", "cube.obj", *SIZE, "--backend", "cpu", "-o", "tex.png"],
          files={"cube.obj": cube_obj(), "cube.mtl": CUBE_MTL, "tex.png": TEX}, expect="error", names=("tex.png",))
    c.add("outputs", "o-is-gltf-image", ["render", "m.gltf", *SIZE, "--backend", "cpu", "-o", "tex.png"],
          files={"m.gltf": jtext(gltf_doc(texture=True)), "tex.png": TEX}, expect="error", names=("tex.png",))
    # compare's folders and files.
    cm = ["compare", "scene.json", *SIZE, "--methods", "stsv/cpu", "--backend", "cpu"]

    def addc(name, extra, files=None, exp="error", names=(), **kw):
        f = dict(sf)
        f.update(files or {})
        c.add("outputs", name, cm + list(extra), files=f, expect=exp, names=names, **kw)

    addc("compare-out-file", ["--out", "cmp"], {"cmp": "x"}, names=("cmp",))
    addc("compare-out-fifo", ["--out", "cmp"], {"cmp": Fifo()}, names=("cmp",))
    addc("compare-out-equals-report", ["--out", "cmp", "--report", "cmp"], names=("cmp",))
    addc("compare-out-equals-report-spelled", ["--out", "cmp", "--report", "./cmp/"], names=("cmp",))
    addc("compare-sheet-in-out", ["--out", "cmp", "--sheet", "cmp/stsv_cpu_lit.png"], names=("stsv_cpu_lit.png",))
    addc("compare-json-dir", ["--json", "t.json"], {"t.json": Dir()}, names=("t.json",))
    addc("compare-json-scene", ["--json", "scene.json"], names=("scene.json",))
    addc("compare-sheet-texture", ["--sheet", "tex.png"], names=("tex.png",))
    addc("compare-report-file", ["--report", "rep"], {"rep": "x"}, names=("rep",))
    addc("compare-out-ok", ["--out", "cmp", "--json", "t.json", "--sheet", "s.png"], exp="ok")
    addc("compare-out-missing-parent", ["--out", "a/b/c"], exp="either")
    d = set_path(scene_dict(), ("materials", 2, "alphaTexture"), "stsv_cpu_lit.png")
    c.add("outputs", "compare-out-overwrites-texture", cm + ["--out", "."],
          files={"scene.json": jtext(d), "stsv_cpu_lit.png": TEX}, expect="error", names=("stsv_cpu_lit.png",))
    bm = ["bench", "scene.json", "--size", "32x24", "--samples", "16", "--methods", "stsv", "--backends", "cpu",
          "--repeat", "1", "--warmup", "0"]
    for label, extra, files, nm in [("json-dir", ["--json", "b.json"], {"b.json": Dir()}, "b.json"),
                                    ("json-fifo", ["--json", "b.json"], {"b.json": Fifo()}, "b.json"),
                                    ("json-scene", ["--json", "scene.json"], {}, "scene.json"),
                                    ("json-dev-null", ["--json", "/dev/null"], {}, "/dev/null")]:
        f = dict(sf)
        f.update(files)
        c.add("outputs", "bench-" + label, bm + extra, files=f, expect="error", names=(nm,))
    c.add("outputs", "bench-json-is-presets", ["bench", "--presets", "p.json", "--preset", "tiny", "--json", "p.json"],
          files={"p.json": PRESETS_OK}, expect="error", names=("p.json",))


# ----------------------------------------------------------------------------------------------
# Environment

ICD_MISSING_LIB = json.dumps({"file_format_version": "1.0.0",
                              "ICD": {"library_path": "/nonexistent/libvulkan_x.so", "api_version": "1.3.0"}})
ICD_NOT_ELF = json.dumps({"file_format_version": "1.0.0", "ICD": {"library_path": "/etc/passwd", "api_version": "1.3.0"}})


def env_surface(c: Cases, shader_src: Path | None):
    manifests = [("missing", None, "missing.json"), ("empty-object", "{}", "m.json"), ("empty-file", "", "m.json"),
                 ("garbage", b"\0\xff\xfe garbage \x01", "m.json"), ("directory", Dir(), "m.json"),
                 ("fifo", Fifo(), "m.json"), ("missing-library", ICD_MISSING_LIB, "m.json"),
                 ("not-elf", ICD_NOT_ELF, "m.json"), ("no-icd", json.dumps({"file_format_version": "1.0.0"}), "m.json")]
    vk = ["render", "fence", *SIZE, "--backend", "vulkan", "-o", "out.png"]
    cpu = ["render", "fence", *SIZE, "--backend", "cpu", "-o", "out.png"]
    for var in ("VK_DRIVER_FILES", "VK_ICD_FILENAMES"):
        for label, content, fname in manifests:
            if var == "VK_ICD_FILENAMES" and label not in ("missing", "garbage", "fifo", "missing-library"):
                continue
            files = {} if content is None else {fname: content}
            env = {var: "$CASE/" + fname}
            c.add("env", "%s=%s-vulkan" % (var, label), vk, files=files, env=env, expect="error", names=(fname,))
            c.add("env", "%s=%s-cpu" % (var, label), cpu, files=files, env=env, expect="ok", check=sees_scene())
            c.add("env", "%s=%s-info" % (var, label), ["info"], files=files, env=env, expect="ok",
                  check=stdout_has(r"vulkan: unavailable.*" + re.escape(fname), "info must say vulkan is unavailable, naming " + fname))
        c.add("env", "%s=empty-string-vulkan" % var, vk, env={var: ""}, expect="either")
    for label, content in [("missing", None), ("garbage", b"\0garbage"), ("not-elf", Symlink("/etc/passwd")),
                           ("directory", Dir())]:
        files = {} if content is None else {"libvk.so": content}
        env = {"STSV_VULKAN_LOADER": "$CASE/libvk.so"}
        c.add("env", "STSV_VULKAN_LOADER=%s-vulkan" % label, vk, files=files, env=env, expect="error", names=("libvk.so",))
        c.add("env", "STSV_VULKAN_LOADER=%s-cpu" % label, cpu, files=files, env=env, expect="ok")
        c.add("env", "STSV_VULKAN_LOADER=%s-info" % label, ["info"], files=files, env=env, expect="ok")
    shader_cases = [("missing", {}, "shaders"), ("empty-dir", {"shaders": Dir()}, "shaders"),
                    ("a-file", {"shaders": "x"}, "shaders")]
    if shader_src and shader_src.is_dir():
        # The checkout's shader set as STSV_SHADER_DIR reads it: every file named by its path from
        # the root (volumes/shaders/stsv.frag, volumes/stsv_dh.h), in the case's shaders/ folder.
        tree = {}
        for p in sorted(shader_src.rglob("*")):
            if p.is_file() and (p.suffix in (".glsl", ".comp", ".frag", ".vert", ".geom", ".mesh", ".task", ".h")) and \
                    "build" not in p.parts and ".git" not in p.parts and p.stat().st_size < 2 * MiB:
                rel = p.relative_to(shader_src)
                if rel.parts[0] in ("volumes", "wedges", "shadowmaps", "sampling", "scene", "core", "render", "reference", "gpu"):
                    tree["shaders/" + rel.as_posix()] = p.read_bytes()
        broken = dict(tree)
        frag = [k for k in tree if k.endswith(".frag")]
        if frag:
            broken[frag[0]] = b"#version 450\nvoid main() { this is not glsl; }\n"
            shader_cases.append(("broken-" + Path(frag[0]).name, broken, Path(frag[0]).name))
    for label, files, nm in shader_cases:
        env = {"STSV_SHADER_DIR": "$CASE/shaders"}
        c.add("env", "STSV_SHADER_DIR=%s-vulkan" % label, vk, files=files, env=env, expect="error", names=(nm,),
              timeout=120)
        c.add("env", "STSV_SHADER_DIR=%s-cpu" % label, cpu, files=files, env=env, expect="ok")
    cv = ["compare", "fence", *SIZE, "--methods", "stsv/cpu", "--backend", "cpu", "--converged", "2"]
    for label, files, env, exp in [
            ("cache-is-file", {"cache": "x"}, {"STSV_CACHE_DIR": "$CASE/cache"}, "either"),
            ("cache-is-fifo", {"cache": Fifo()}, {"STSV_CACHE_DIR": "$CASE/cache"}, "either"),
            ("cache-unwritable", {}, {"STSV_CACHE_DIR": "/proc/stsv-cache"}, "either"),
            ("cache-empty", {}, {"STSV_CACHE_DIR": "", "XDG_CACHE_HOME": "$CASE/xdg"}, "either"),
            ("no-home", {}, {"STSV_CACHE_DIR": None, "XDG_CACHE_HOME": None, "HOME": None}, "either"),
            ("cache-corrupt-entry", {}, {"STSV_CACHE_DIR": "$CASE/cache"}, "ok")]:
        c.add("env", "compare-converged-" + label, cv, files=files, env=env, expect=exp, outputs=None)
    c.add("env", "locale-c-utf8", cpu, env={"LC_ALL": "C.UTF-8"}, expect="ok", check=sees_scene())
    c.add("env", "locale-de", cpu, env={"LC_ALL": "de_DE.UTF-8", "LANG": "de_DE.UTF-8"}, expect="ok", check=sees_scene())
    c.add("env", "tmpdir-missing", cpu, env={"TMPDIR": "/nonexistent"}, expect="ok")
    c.add("env", "validation-no-layer-path", vk + ["--validation"], env={"VK_LAYER_PATH": "/nonexistent",
                                                                       "VK_ADD_LAYER_PATH": None}, expect="either")


# ----------------------------------------------------------------------------------------------
# Geometry the methods find hard: lights flush with a ceiling, scenes far from the origin,
# the two backends on the same scene

GEOMETRY_METHODS = [("reference", "cpu"), ("stsv", "cpu"), ("dcs", "cpu"), ("pcss", "cpu"), ("stsv", "vulkan"),
                    ("dcs", "vulkan")]


def geometry_surface(c: Cases):
    def args(method, backend):
        return ["render", "scene.json", *SIZE, "--backend", backend, "--method", method, "-o", "out.png",
                "--visibility", "v.npy"]

    control = scene_files()
    for method, backend in GEOMETRY_METHODS:
        a = args(method, backend)
        for label, ceiling, dark in [("flush-facing-down", (3.0, "down", False), False),
                                     ("flush-facing-up", (3.0, "up", False), False),
                                     ("flush-double-sided", (3.0, "down", True), False),
                                     ("ceiling-1e-4-above", (3.0001, "down", True), False),
                                     ("ceiling-1e-3-below-light", (2.999, "down", True), True)]:
            if backend == "vulkan" and label not in ("flush-facing-down", "ceiling-1e-3-below-light"):
                continue
            c.add("geometry", "ceiling-%s-%s/%s" % (label, method, backend), a,
                  files=scene_files(ceiling=ceiling), expect="ok", timeout=120,
                  check=vis_matches_aux(control, a, "light flush with a ceiling" if not dark else "light above the ceiling",
                                        dark=dark),
                  desc="the floor's visibility equals the scene without a ceiling" if not dark else
                  "the light is above the ceiling: the floor is in shadow")
        disk = {"type": "disk", "position": [-2, 3, 0], "normal": [0, -1, 0], "radius": 0.3, "radiance": 40}
        if backend == "cpu" and method in ("reference", "stsv"):
            c.add("geometry", "ceiling-flush-disk-%s/%s" % (method, backend), a,
                  files=scene_files(ceiling=(3.0, "down", False), light=disk), expect="ok",
                  check=vis_matches_aux(scene_files(light=disk), a, "disk light flush with a ceiling"))
        for off in (1e3, 1e6, 1e7, 1e8):
            if backend == "vulkan" and method == "dcs" and off == 1e7:
                continue
            c.add("geometry", "offset-%g-%s/%s" % (off, method, backend), a,
                  files=scene_files(off=(off, off, off)), expect="either", timeout=120,
                  check=vis_matches_aux(control, a, "scene translated by %g" % off, mean_tol=0.05, frac_tol=0.05),
                  desc="the same scene translated: the same picture, or a clean refusal")
    a = args("stsv", "cpu")
    for off in (1e6, 1e8):
        d = scene_dict()
        for mesh in d["meshes"]:
            t = mesh.setdefault("transform", {})
            tr = t.get("translate", [0, 0, 0])
            t["translate"] = [tr[0] + off, tr[1] + off, tr[2] + off]
        d["lights"][0]["position"] = [x + off for x in d["lights"][0]["position"]]
        d["camera"]["eye"] = [x + off for x in d["camera"]["eye"]]
        d["camera"]["target"] = [x + off for x in d["camera"]["target"]]
        c.add("geometry", "offset-transform-%g-stsv/cpu" % off, a, files=scene_files(d), expect="either",
              check=vis_matches_aux(control, a, "scene translated by %g (transform)" % off, mean_tol=0.05, frac_tol=0.05))
    for method, backend in [("stsv", "cpu"), ("stsv", "vulkan"), ("reference", "cpu")]:
        a = args(method, backend)
        c.add("geometry", "ground-10km-%s/%s" % (method, backend), a, files=scene_files(floor_half=10000.0),
              expect="ok", check=vis_matches_aux(control, a, "a 20 km floor", mean_tol=0.03, frac_tol=0.03),
              desc="docs: robust to a 10 km ground")
    # Both backends see the same points: Vulkan against the CPU's picture of the same method.
    for method in ("stsv", "dcs", "pcss", "pw", "dcs+stsv", "pw+stsv", "peel", "avsm"):
        a = args(method, "vulkan")
        c.add("geometry", "backends-agree-%s" % method, a, files=control, expect="ok", timeout=120,
              check=vis_matches_aux(control, args(method, "cpu"), "vulkan against cpu", mean_tol=0.03, frac_tol=0.03))
    # Vulkan options.
    vk = ["render", "fence", *SIZE, "--backend", "vulkan", "-o", "out.png"]
    for v, exp in [("hull", "ok"), ("geometry", "ok"), ("auto", "ok"), ("mesh", "either")]:
        c.add("geometry", "vulkan-extrusion-" + v, vk + ["--extrusion", v], expect=exp, timeout=120,
              names=("mesh",) if exp != "ok" else (), check=sees_scene() if exp == "ok" else None)
    for v, exp in [("", "error"), ("-1", "error"), ("99", "error"), ("nonexistent", "error"), ("0", "ok"),
                   ("llvmpipe", "ok"), ("LLVMPIPE", "ok"), ("4294967296", "error")]:
        c.add("geometry", "vulkan-device=" + v, vk + ["--device", v], expect=exp, names=("--device",) if exp == "error" and v == "" else (),
              check=sees_scene() if exp == "ok" else None)
    c.add("geometry", "vulkan-validation", vk + ["--validation"], expect="ok", timeout=120,
          check=lambda ctx: "validation messages on stderr: " + ctx.stderr.strip().splitlines()[0]
          if re.search(r"(?i)validation (error|warning)|VUID", ctx.stderr) else None)
    vk_base = ["render", "fence", "--backend", "vulkan", "-o", "out.png"]
    for param in (["--method", "pcss", "--param", "sm_size=4096", *SIZE], ["--method", "csm", "--param", "sm_size=2048", *SIZE],
                  ["--method", "avsm", "--param", "avsm_size=4096", *SIZE], ["--method", "peel", "--param", "peel_size=1024", *SIZE],
                  ["--method", "stsv", "--size", "4096x4096", "--samples", "16"],
                  ["--method", "stsv", "--samples", "256", "--size", "2048x2048"]):
        c.add("geometry", "vulkan-large-" + "-".join(param[1:4]).replace("--", ""), vk_base + param, expect="either",
              budget_mb=BUDGET_LIMIT, timeout=180, desc="held to --max-memory 1G: refused, or run within it")
    c.add("geometry", "vulkan-knot-max-sides", ["render", "knot", *SIZE, "--backend", "vulkan", "-o", "out.png",
                                                "--method", "dcs", "--set", "sides=200"], expect="either",
          budget_mb=BUDGET_LIMIT, timeout=180)


# ----------------------------------------------------------------------------------------------
# Main

SURFACES = ["json", "png", "obj", "off", "gltf", "npy", "cli", "knobs", "params", "outputs", "env", "geometry"]


def build_cases(info: dict, shader_src: Path | None) -> list[Case]:
    c = Cases()
    json_surface(c)
    png_surface(c)
    obj_surface(c)
    off_surface(c)
    gltf_surface(c)
    npy_surface(c)
    cli_surface(c)
    knobs_surface(c, info)
    params_surface(c, info)
    outputs_surface(c)
    env_surface(c, shader_src)
    geometry_surface(c)
    return c.items


def first_line(r: Result) -> str:
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    for ln in lines:
        if ERROR_LINE.match(ln) or "internal error" in ln or "terminate" in ln:
            return ln[:300]
    for ln in lines:
        if not ln.startswith(("stsv: warning:", "wrote ", "note:")):
            return ln[:300]
    return lines[0][:300] if lines else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("stsv", type=Path, help="the stsv binary (BUILD/cli/stsv)")
    ap.add_argument("--out", type=Path, default=Path("probe.json"), help="JSON report (default probe.json)")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="cases run at once (default 2)")
    ap.add_argument("--only", default="", help="run only the cases whose id matches this regular expression")
    ap.add_argument("--keep", type=Path, help="generate into this folder and keep it (else a temporary one)")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    ap.add_argument("--no-vulkan", action="store_true", help="leave out the cases that run --backend vulkan")
    args = ap.parse_args()

    stsv = args.stsv.resolve()
    if not stsv.is_file() or not os.access(stsv, os.X_OK):
        sys.exit("probe: %s is not an executable" % stsv)
    info_run = subprocess.run([str(stsv), "info", "--json"], capture_output=True, text=True, timeout=120)
    try:
        info = json.loads(info_run.stdout)
    except json.JSONDecodeError:
        sys.exit("probe: `stsv info --json` did not print JSON: " + info_run.stderr[:300])
    shader_src = Path(__file__).resolve().parents[2]  # the checkout's root: the shader set's top
    cases = build_cases(info, shader_src if (shader_src / "volumes" / "shaders").is_dir() else None)
    if args.only:
        rx = re.compile(args.only)
        cases = [k for k in cases if rx.search(k.cid)]
    if args.no_vulkan:
        cases = [k for k in cases if "vulkan" not in k.args and "VK_" not in k.cid and "STSV_VULKAN" not in k.cid
                 and "STSV_SHADER" not in k.cid]
    if args.list:
        for k in cases:
            print(k.cid, "\t", k.expect, "\t", " ".join(shquote(a) for a in k.args)[:200])
        print("%d cases" % len(cases))
        return

    if args.keep:
        work = args.keep.resolve()
        work.mkdir(parents=True, exist_ok=True)
    else:
        work = Path(tempfile.mkdtemp(prefix="stsv-probe-"))
    probe = Probe(stsv, work, shutil.which("prlimit") is not None)
    print("stsv probe: %d cases, %d at once, inputs in %s" % (len(cases), args.jobs, work), file=sys.stderr, flush=True)
    t0 = time.monotonic()
    results: list[Result | None] = [None] * len(cases)
    done = [0]
    lock = threading.Lock()

    def one(i):
        try:
            r = probe.run(cases[i])
        except Exception as e:  # the probe's own failure: reported, the other cases still run
            r = Result(cases[i], klass="probe-error", detail="%s: %s" % (type(e).__name__, e))
        results[i] = r
        with lock:
            done[0] += 1
            if r.klass not in CLEAN:
                print("  [%d/%d] %-13s %s: %s" % (done[0], len(cases), r.klass, r.case.cid, r.detail[:160]),
                      file=sys.stderr, flush=True)
            elif done[0] % 50 == 0:
                print("  [%d/%d] %.0f s" % (done[0], len(cases), time.monotonic() - t0), file=sys.stderr, flush=True)

    try:
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            list(pool.map(one, range(len(cases))))
    finally:
        if not args.keep:
            for dirpath, dirnames, _ in os.walk(work):
                for dn in dirnames:
                    try:
                        os.chmod(os.path.join(dirpath, dn), 0o755)
                    except OSError:
                        pass
            shutil.rmtree(work, ignore_errors=True)
    elapsed = time.monotonic() - t0
    results = [r for r in results if r is not None]

    by_class = {k: 0 for k in CLASSES}
    by_surface: dict[str, dict[str, int]] = {}
    for r in results:
        by_class[r.klass] += 1
        s = by_surface.setdefault(r.case.surface, {k: 0 for k in CLASSES})
        s[r.klass] += 1
    left = [r for r in results if r.klass == "clean-error" and r.left_files]
    version = subprocess.run([str(stsv), "--version"], capture_output=True, text=True).stdout.strip()
    report = {
        "stsv": str(stsv),
        "version": version,
        "cases": len(results),
        "elapsed_s": round(elapsed, 1),
        "caps": {"address_space_bytes": AS_CAP, "timeout_s": DEFAULT_TIMEOUT, "max_memory": MAX_MEMORY,
                 "budget_small_mb": BUDGET_SMALL, "budget_limit_mb": BUDGET_LIMIT},
        "counts": by_class,
        "by_surface": by_surface,
        "non_clean": [
            {"id": r.case.cid, "surface": r.case.surface, "class": r.klass, "detail": r.detail,
             "expect": r.case.expect, "desc": r.case.desc if r.case.desc != r.case.cid.split("/", 1)[1] else "",
             "command": r.command, "exit": r.rc, "signal": r.signal, "wall_s": r.wall_s, "maxrss_mb": r.maxrss_mb,
             "stderr_first": first_line(r)}
            for r in results if r.klass not in CLEAN],
        "errors_that_left_files": [{"id": r.case.cid, "files": r.left_files[:5]} for r in left],
        "all": [{"id": r.case.cid, "class": r.klass, "exit": r.rc, "signal": r.signal, "wall_s": r.wall_s,
                 "maxrss_mb": r.maxrss_mb, "stderr_first": first_line(r)} for r in results],
    }
    args.out.write_text(json.dumps(report, indent=1, ensure_ascii=True) + "\n")

    print("\nstsv probe: %s, %d cases in %.0f s (inputs: $W = %s%s)" % (
        version, len(results), elapsed, work, "" if args.keep else ", removed"))
    cols = [k for k in CLASSES]
    short = {"clean-error": "clean", "accepted": "ok", "crash": "crash", "hang": "hang", "unbounded": "unbnd",
             "silent-wrong": "wrong", "false-refusal": "f-ref", "unclear-error": "unclr", "questionable": "quest",
             "probe-error": "probe"}
    print("%-10s" % "surface" + "".join("%7s" % short[k] for k in cols) + "%7s" % "total")
    for s in SURFACES:
        if s in by_surface:
            row = by_surface[s]
            print("%-10s" % s + "".join("%7d" % row[k] for k in cols) + "%7d" % sum(row.values()))
    print("%-10s" % "all" + "".join("%7d" % by_class[k] for k in cols) + "%7d" % len(results))
    nc = report["non_clean"]
    if nc:
        print("\nnon-clean cases (%d):" % len(nc))
        for k in CLASSES:
            rows = [x for x in nc if x["class"] == k]
            if not rows:
                continue
            print("\n== %s (%d)" % (k, len(rows)))
            for x in rows:
                print("- %s: %s" % (x["id"], x["detail"]))
                print("    exit %s%s, %.1f s, %.0f MB; stderr: %s" % (
                    x["exit"], " (%s)" % x["signal"] if x["signal"] else "", x["wall_s"], x["maxrss_mb"],
                    x["stderr_first"][:200]))
                print("    $ " + x["command"][:400])
    if left:
        print("\nclean errors that left files behind (%d): %s" % (
            len(left), ", ".join("%s (%s)" % (r.case.cid, ", ".join(r.left_files[:3])) for r in left[:20])))
    print("\nwrote %s" % args.out)


if __name__ == "__main__":
    main()
