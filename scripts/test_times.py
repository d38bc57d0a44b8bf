#!/usr/bin/env python3
"""The slowest tests of a ctest run, from its JUnit report.

Usage: test_times.py CTEST_JUNIT_XML [N]

Prints the N (default 15) slowest tests with their seconds, and the sum of
all tests' times beside the number of tests, so that growth in the suite's
cost shows in every run's log.
"""
import sys
import xml.etree.ElementTree as ET


def main() -> int:
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    path = sys.argv[1]
    count = int(sys.argv[2]) if len(sys.argv) == 3 else 15
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"test_times: {path}: {e}", file=sys.stderr)
        return 1
    times = []
    for case in root.iter("testcase"):
        try:
            seconds = float(case.get("time", "0"))
        except ValueError:
            seconds = 0.0
        # A parameterised gtest's name carries "  # GetParam() = ..." after it.
        name = case.get("name", "?").split("  # ")[0]
        times.append((seconds, name, case.get("status", "")))
    times.sort(reverse=True)
    total = sum(t for t, _, _ in times)
    print(f"-- {len(times)} tests, {total:.0f} s of test time; the {min(count, len(times))} slowest:")
    for seconds, name, status in times[:count]:
        mark = "" if status in ("run", "") else f"  ({status})"
        print(f"   {seconds:7.1f} s  {name}{mark}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
