#!/usr/bin/env python3
"""What the ASan pass of CI does not run: the source lines that only the
tests of test/asan_exclude.txt reach.

CI runs the unit tests twice, in Release and under AddressSanitizer + UBSan.
Under the sanitizers a calibration runs 15-50x slower, so the ASan pass
leaves out tests that exercise nothing the rest of it does not. This script
checks that claim with gcov line coverage (lines of src/, apps/, include/):

  python3 scripts/asan_coverage.py BUILD_DIR [--only REGEX]

It configures BUILD_DIR as a coverage build (-O1 --coverage, no benchmarks,
no Python), builds it, runs the ASan pass's set of tests once (collecting
the lines it reaches), then each excluded test on its own (or those matching
--only), and prints, per excluded test, the lines it reaches that the ASan
set does not. Line coverage is a proxy: the same line run on other data can
touch other memory. Takes about 15 minutes on 2 cores.
"""
import argparse
import glob
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCES = tuple(os.path.join(HERE, d) + os.sep for d in ("src", "apps", "include"))


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, **kw)


def configure_and_build(build):
    robots = os.path.join(os.path.dirname(HERE), "shared", "robots")
    run(["cmake", "-S", HERE, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
         "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG", "-DCMAKE_CXX_FLAGS=--coverage",
         "-DCMAKE_EXE_LINKER_FLAGS=--coverage", "-DCMAKE_SHARED_LINKER_FLAGS=--coverage",
         "-DSTAC_BUILD_BENCHMARKS=OFF", "-DSTAC_PYTHON=OFF",
         "-DSTAC_ROBOTS_DIR=" + (robots if os.path.isdir(robots) else "")],
        stdout=subprocess.DEVNULL)
    built = subprocess.run(["cmake", "--build", build], capture_output=True, text=True)
    if built.returncode != 0:
        sys.exit(built.stdout[-4000:] + built.stderr[-4000:])


def clear_counters(build):
    for f in glob.glob(os.path.join(build, "**", "*.gcda"), recursive=True):
        os.remove(f)


def covered_lines(build):
    """{(file, line)} with a non-zero count in the build's .gcda files."""
    gcdas = glob.glob(os.path.join(build, "**", "*.gcda"), recursive=True)
    lines = set()
    for i in range(0, len(gcdas), 20):
        out = subprocess.run(["gcov", "--stdout", "--json-format"] + gcdas[i:i + 20],
                             capture_output=True, text=True, cwd=build).stdout
        for row in out.splitlines():
            if not row.startswith("{"):
                continue
            for f in json.loads(row)["files"]:
                name = os.path.normpath(os.path.join(build, f["file"]))
                if name.startswith(SOURCES):
                    lines |= {(name, l["line_number"]) for l in f["lines"] if l["count"] > 0}
    return lines


def ctest_names(build, *args):
    out = subprocess.run(["ctest", "-N", *args], capture_output=True, text=True, cwd=build).stdout
    return [l.split(":", 1)[1].strip() for l in out.splitlines() if l.strip().startswith("Test")
            and ":" in l]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build")
    ap.add_argument("--only", default="", help="regex: only the excluded tests matching it")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    exclude = open(os.path.join(HERE, "test", "asan_exclude.txt")).read().strip()
    configure_and_build(build)

    clear_counters(build)
    subprocess.run(["ctest", "-j", str(os.cpu_count() or 2), "-L", "unit", "-E", exclude],
                   cwd=build, stdout=subprocess.DEVNULL)
    asan_set = covered_lines(build)
    print(f"ASan set: {len(asan_set)} lines reached", flush=True)

    excluded = set(ctest_names(build, "-L", "unit")) - set(ctest_names(build, "-L", "unit", "-E",
                                                                      exclude))
    if args.only:
        excluded = set(ctest_names(build, "-R", args.only)) & excluded
    lost = set()
    for name in sorted(excluded):
        clear_counters(build)
        subprocess.run(["ctest", "-R", "^" + name.replace(".", r"\.") + "$"], cwd=build,
                       stdout=subprocess.DEVNULL)
        only_here = covered_lines(build) - asan_set
        lost |= only_here
        print(f"{name}: {len(only_here)} lines the ASan set does not reach", flush=True)
        for f, l in sorted(only_here)[:20]:
            print(f"    {os.path.relpath(f, HERE)}:{l}")
    print(f"lines only excluded tests reach: {len(lost)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
