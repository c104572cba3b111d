#!/usr/bin/env python3
"""Every TEST_CASE in the sources is exactly one ctest entry, and every entry is a TEST_CASE.

Guards against tests that never run but report Passed: catch_discover_tests splits a name at
';' into entries that match no test case (Catch2 v2 then exits 0 with nothing run), and a
test case whose name the discovery cannot pass back would be lost the same way.
usage: check_discovery.py BUILD_DIR SOURCE_DIR EXECUTABLE...
"""
import pathlib
import re
import subprocess
import sys

build, source, executables = sys.argv[1], pathlib.Path(sys.argv[2]), set(sys.argv[3:])

# The TEST_CASE names in the sources, with the file each comes from.
declared = {}
literal = re.compile(r'^\s*TEST_CASE\s*\(\s*"((?:[^"\\]|\\.)*)"', re.M)
for path in sorted(source.rglob('*.cpp')):
    for m in literal.finditer(path.read_text(encoding='utf-8')):
        name = m.group(1).replace('\\"', '"').replace('\\\\', '\\')
        if name in declared:
            print('%s: TEST_CASE "%s" is also declared in %s' % (path, name, declared[name]))
            sys.exit(1)
        declared[name] = path
    if re.search(r'^\s*(TEMPLATE_TEST_CASE|SCENARIO|TEST_CASE_METHOD)\w*\s*\(', path.read_text(encoding='utf-8'), re.M):
        print('%s: uses a test macro this check does not read; extend tests/check_discovery.py' % path)
        sys.exit(1)

listing = subprocess.run(['ctest', '--test-dir', build, '-N'], check=True, capture_output=True, text=True).stdout
entries = [m.group(1) for m in re.finditer(r'^\s*Test\s+#\d+: (.*)$', listing, re.M)]
discovered = {}
for entry in entries:
    # catch_discover_tests names an entry "EXECUTABLE:NAME" (ctest drops the prefix's space)
    exe, sep, name = entry.partition(':')
    if sep and exe in executables:
        discovered.setdefault(name.lstrip(' '), []).append(exe)

problems = []
for name, path in declared.items():
    if name not in discovered:
        problems.append('%s: TEST_CASE "%s" is not a ctest entry (its name is split or lost by discovery)' % (path, name))
    elif len(discovered[name]) > 1:
        problems.append('%s: TEST_CASE "%s" is an entry of several executables: %s' % (path, name, discovered[name]))
for name, exes in discovered.items():
    if name not in declared:
        problems.append('ctest entry "%s: %s" is no TEST_CASE of the sources (a piece of a split name?)' % (exes[0], name))
for p in problems:
    print(p)
print('%d TEST_CASEs in the sources, %d Catch2 entries in ctest' % (len(declared), sum(map(len, discovered.values()))))
sys.exit(1 if problems else 0)
