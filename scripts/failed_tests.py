#!/usr/bin/python3
"""Lists the failed and errored test cases of the JUnit XML files under a test results folder,
one line each ("<file>: <class>.<name>: <first line of the message>"), so a red run names what
failed next to its summary line.
Usage: scripts/failed_tests.py RESULTS_DIR"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    if len(sys.argv) != 2 or not pathlib.Path(sys.argv[1]).is_dir():
        sys.exit(__doc__)
    for xml in sorted(pathlib.Path(sys.argv[1]).rglob("*.xml")):
        try:
            root = ET.parse(xml).getroot()
        except ET.ParseError as e:
            print("%s: unreadable test results (%s)" % (xml.name, e))
            continue
        for case in root.iter("testcase"):
            for bad in list(case.findall("failure")) + list(case.findall("error")):
                text = (bad.get("message") or bad.text or "").strip().splitlines()
                print("%s: %s.%s: %s" % (xml.name, case.get("classname", ""), case.get("name", ""),
                                         text[0][:200] if text else bad.tag))


if __name__ == "__main__":
    main()
