#!/usr/bin/env python3
"""`make lint` reaches every header of the project: .clang-tidy's HeaderFilterRegex matches each
header of the checkout (clang-tidy sees them by absolute path, wherever the checkout lies) and no
header of the system (whose findings are not the project's to fix). A new folder of headers that
the filter leaves out fails here, naming the folder.

    lint_scope_test.py SOURCE_DIR      # exit 0: the filter covers every folder, and only those
"""
import pathlib
import re
import subprocess
import sys

# Headers of the libraries the project includes, as clang-tidy names them.
SYSTEM_HEADERS = [
    "/usr/include/vulkan/vulkan_core.h",
    "/usr/include/embree3/rtcore.h",
    "/usr/include/glm/detail/setup.hpp",
    "/usr/include/OpenMesh/Core/Mesh/PolyMeshT.hh",
    "/usr/include/gtest/internal/gtest-internal.h",
    "/usr/include/tbb/parallel_for.h",
    "/usr/include/OpenEXR/ImfHeader.h",
    "/usr/include/stb/stb_image_write.h",
    "/usr/include/c++/12/bits/stl_vector.h",
    "/usr/include/x86_64-linux-gnu/sys/types.h",
]


def header_filter(root):
    for line in (root / ".clang-tidy").read_text().splitlines():
        m = re.match(r"HeaderFilterRegex:\s*'(.*)'\s*$", line)
        if m:
            return re.compile(m.group(1))
    sys.exit(".clang-tidy: no HeaderFilterRegex")


def project_headers(root):
    out = subprocess.run(["git", "-C", str(root), "ls-files", "*.h"], capture_output=True, text=True)
    if out.returncode != 0 or not out.stdout.strip():
        sys.exit(f"{root}: cannot list the checkout's headers (git ls-files: {out.stderr.strip()})")
    return [root.resolve() / p for p in out.stdout.split()]


def check(pattern, headers):
    """The problems: folders whose headers the filter misses, system headers it takes."""
    problems = []
    missed = sorted({str(h.parent) for h in headers if not pattern.search(str(h))})
    problems += [f"{folder}/: its headers are outside HeaderFilterRegex" for folder in missed]
    problems += [f"{h}: a system header inside HeaderFilterRegex" for h in SYSTEM_HEADERS if pattern.search(h)]
    return problems


def main():
    root = pathlib.Path(sys.argv[1])
    pattern = header_filter(root)
    headers = project_headers(root)
    # The check itself can fail: a header in a folder the filter does not name is reported.
    planted = check(pattern, [root.resolve() / "newfolder" / "planted.h"])
    if len(planted) != 1 or "newfolder" not in planted[0]:
        sys.exit(f"self-test: a header in a new folder was not reported ({planted})")
    problems = check(pattern, headers)
    for p in problems:
        print(p)
    print(f"{len(headers)} headers in {len({h.parent for h in headers})} folders; {len(problems)} problems")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
