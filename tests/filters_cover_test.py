#!/usr/bin/python3
"""Every GoogleTest test of the shared test executables is run by some ctest test.

Each tests/<concern>/*test_*.cpp is a ctest test that runs its own suites through
--gtest_filter (tests/CMakeLists.txt, hydrosoft_file_filter, which reads the suite names
off the TEST lines). A test the filters miss would build and never run: this lists every
executable's tests (--gtest_list_tests) and fails on any that no filter of that executable
matches.

    filters_cover_test.py BUILD_DIR
"""
import collections
import fnmatch
import json
import subprocess
import sys

build = sys.argv[1]
listing = json.loads(subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True,
                                    capture_output=True, text=True).stdout)
filters = collections.defaultdict(list)
for test in listing["tests"]:
    command = test.get("command", [])
    for i, word in enumerate(command):
        if word.startswith("--gtest_filter="):
            filters[command[i - 1]].extend(word.split("=", 1)[1].split(":"))
if not filters:
    sys.exit("no ctest test runs a --gtest_filter: tests/CMakeLists.txt changed?")
missed = []
for exe, patterns in sorted(filters.items()):
    out = subprocess.run([exe, "--gtest_list_tests"], check=True, capture_output=True,
                         text=True).stdout
    suite, count = None, 0
    for line in out.splitlines():
        if not line.startswith(" "):
            suite = line.split()[0]
            continue
        name = suite + line.split()[0]
        count += 1
        if not any(fnmatch.fnmatchcase(name, p) for p in patterns):
            missed.append(f"{exe}: {name}")
    print(f"{exe}: {count} tests, each run by a ctest test")
if missed:
    sys.exit("run by no ctest test (its TEST line not found by hydrosoft_file_filter):\n  " +
             "\n  ".join(missed))
