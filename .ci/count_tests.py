"""Fail (exit 1) when a pytest junit report shows that no test ran.

Usage: python3 .ci/count_tests.py report.xml
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET


def executed(path: str) -> tuple[int, int]:
    """(collected, executed) test counts of a junit XML report."""
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    tests = sum(int(s.get("tests", 0)) for s in suites)
    skipped = sum(int(s.get("skipped", 0)) for s in suites)
    return tests, tests - skipped


def main(argv: list[str]) -> int:
    tests, ran = executed(argv[1])
    print(f"ci: {tests} tests collected, {ran} ran, {tests - ran} skipped")
    if ran <= 0:
        print("ci: no test ran", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
