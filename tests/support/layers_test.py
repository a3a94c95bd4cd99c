#!/usr/bin/env python3
"""The layers point down (ARCHITECTURE.md): every #include of the source tree checked against the
rules below. The math of the families (their *_dh.h headers and the folders of shared math) builds
without Vulkan and without a renderer; no Vulkan code reaches the ground truth (Embree) or the
CPU renderer; the CPU renderer reaches no Vulkan code; the frame code that both backends share
reaches neither backend. A violation is printed as FILE:LINE: the include and the rule it breaks.

    layers_test.py SOURCE_DIR [--families volumes,wedges,shadowmaps]   # exit 0: every rule holds

--families is the build's list of family folders (STSV_FAMILIES in CMakeLists.txt); without it,
the folders that have a cpu/ or vulkan/ side.
"""
import pathlib
import re
import sys

# The folders of math and data that build on the CPU alone (no gpu/, render/, reference/, cli/).
# A family's folder (volumes/ for STSV, wedges/, shadowmaps/) holds its math at the top and its
# backends' sides in cpu/ and vulkan/, which build into render/cpu's and render/vulkan's libraries,
# and its GLSL in shaders/ (render/shaders: what every family's passes share), part of the
# Vulkan side.
DEFAULT_FAMILIES = ("volumes", "wedges", "shadowmaps")


def configure(families):
    """The folder lists the rules read, for the given family folders."""
    global FAMILIES, MATH, CPU, VULKAN, BACKENDS, FAMILY_SIDES, FAMILY_BACKEND
    FAMILIES = tuple(families)
    MATH = ("core/", "sampling/", "scene/") + tuple(f + "/" for f in FAMILIES)
    CPU = ("render/cpu/",) + tuple(f + "/cpu/" for f in FAMILIES)
    VULKAN = ("render/vulkan/", "render/shaders/", "gpu/") + tuple(
        f + side for f in FAMILIES for side in ("/vulkan/", "/shaders/"))
    BACKENDS = CPU + VULKAN
    FAMILY_SIDES = tuple(f + side for f in FAMILIES for side in ("/cpu/", "/vulkan/", "/shaders/"))
    # A family's backend side includes no other family's backend side.
    FAMILY_BACKEND = re.compile("(" + "|".join(map(re.escape, FAMILIES)) + ")/(cpu|vulkan|shaders)/")


configure(DEFAULT_FAMILIES)


def is_math(path):
    return path.startswith(MATH) and not path.startswith(BACKENDS)


# (rule, which files it governs, which includes it forbids)
RULES = [
    ("math builds without a renderer, Vulkan or the ground truth",
     is_math, lambda inc: inc.startswith(("gpu/", "render/", "reference/", "cli/") + FAMILY_SIDES)),
    ("a device/host (*_dh.h) header includes only device/host headers",
     lambda f: f.endswith("_dh.h"), lambda inc: not (inc.endswith("_dh.h") or inc == "core/dh.h")),
    ("the Vulkan side reaches neither the ground truth nor the CPU renderer",
     lambda f: f.startswith(VULKAN), lambda inc: inc.startswith(("reference/",) + CPU)),
    ("the CPU renderer reaches no Vulkan code",
     lambda f: f.startswith(CPU), lambda inc: inc.startswith(VULKAN)),
    ("the Vulkan plumbing (gpu/) knows no renderer",
     lambda f: f.startswith("gpu/"), lambda inc: inc.startswith(("render/",) + FAMILY_SIDES)),
    ("the frame code both backends share reaches neither backend",
     lambda f: f.startswith("render/") and not f.startswith(BACKENDS) and f != "render/renderer.cpp",
     lambda inc: inc.startswith(BACKENDS)),
    ("the ground truth knows no renderer",
     lambda f: f.startswith("reference/"), lambda inc: inc.startswith(("render/", "gpu/") + FAMILY_SIDES)),
]

# Only the techniques files, which compose the families a method row names, may include every
# family's backend side.
COMPOSERS = {"render/cpu/cpu_techniques.cpp", "render/vulkan/vulkan_techniques.cpp"}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCES = ("*.h", "*.cpp", "*.glsl", "*.comp", "*.frag", "*.vert", "*.geom", "*.mesh", "*.task")


def family(path):
    match = FAMILY_BACKEND.match(path)
    return match.group(1) if match else None


def violations(files):
    """files: {relative path: text}. Yields 'FILE:LINE: include "X": rule'."""
    for path, text in sorted(files.items()):
        for number, line in enumerate(text.splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            inc = match.group(1)
            for rule, governs, forbids in RULES:
                if governs(path) and forbids(inc):
                    yield f'{path}:{number}: include "{inc}": {rule}'
            own, other = family(path), family(inc)
            if own and other and own != other and path not in COMPOSERS:
                yield f'{path}:{number}: include "{inc}": a family includes no other family\'s backend'


def tree(root):
    files = {}
    for folder in ("core", "sampling", "scene") + FAMILIES + ("reference", "render", "gpu", "cli"):
        for pattern in SOURCES:
            for path in (root / folder).rglob(pattern):
                files[path.relative_to(root).as_posix()] = path.read_text(encoding="utf-8")
    return files


def self_test():
    """Each rule must catch a planted include, so a rule that matches nothing cannot pass."""
    planted = {
        "wedges/x_dh.h": '#include "render/methods.h"\n',
        "volumes/y_dh.h": '#include "scene/scene.h"\n',
        "render/vulkan/z.cpp": '#include "reference/embree_scene.h"\n',
        "render/cpu/w.cpp": '#include "gpu/device.h"\n',
        "gpu/v.cpp": '#include "render/frame.h"\n',
        "gpu/q.cpp": '#include "wedges/vulkan/gpu_wedge_passes.h"\n',
        "render/frame.cpp": '#include "render/cpu/cpu_renderer.h"\n',
        "reference/u.cpp": '#include "render/methods.h"\n',
        "wedges/cpu/cpu_wedges.h": '#include "volumes/cpu/cpu_stsv.h"\n',
        "volumes/vulkan/gpu_stsv_pass.cpp": '#include "wedges/vulkan/gpu_wedge_passes.h"\n',
    }
    found = list(violations(planted))
    for path in planted:
        if not any(v.startswith(path + ":") for v in found):
            print(f"self-test: the planted include in {path} was not caught", file=sys.stderr)
            return 1
    if list(violations({"render/cpu/cpu_techniques.cpp": '#include "volumes/cpu/cpu_stsv.h"\n'})):
        print("self-test: the techniques file may compose the families", file=sys.stderr)
        return 1
    return 0


def main():
    root = pathlib.Path(sys.argv[1])
    if self_test():
        return 1
    if "--families" in sys.argv:
        configure(sys.argv[sys.argv.index("--families") + 1].split(","))
    else:
        configure(sorted(p.name for p in root.iterdir()
                         if p.name != "render" and ((p / "cpu").is_dir() or (p / "vulkan").is_dir())))
    files = tree(root)
    if len(files) < 100:
        print(f"found only {len(files)} sources under {root}: wrong folder?", file=sys.stderr)
        return 1
    bad = list(violations(files))
    for v in bad:
        print(v, file=sys.stderr)
    print(f"{len(files)} sources, {len(bad)} includes against the layers")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
