#!/usr/bin/env bash
# The layout table (docs/layout.md) against the tree: every folder the table names exists; every
# source folder (src/*, src/*/* with sources, devices, firmware_sim) and every test folder is
# named; every source folder has a test folder at the mirrored path.
# `layout_test.sh SRC --print` lists the folders the table has to name.
set -euo pipefail
root=$1
cd "$root"
table=$(sed -n '/^| folder | holds |/,/^$/p' docs/layout.md)
named=$(grep -o '^| `[^|]*|' <<<"$table" | grep -o '`[^`]*`' | tr -d '`' | sort -u)

sources=$( (ls -d src/*/ src/*/*/ 2>/dev/null; echo devices/; echo firmware_sim/) | sed 's#/$##' |
  while read -r d; do ls "$d"/*.cpp "$d"/*.h >/dev/null 2>&1 && echo "$d"; done | sort -u)
tests=$(cd tests && ls -d */ */*/ 2>/dev/null | sed 's#/$##' | sed 's#^#tests/#' | sort -u)
if [ "${2:-}" = "--print" ]; then printf '%s\n' $sources $tests; exit 0; fi

fail=0
for n in $named; do
  [ -e "$n" ] || { echo "docs/layout.md names '$n', which does not exist"; fail=1; }
done
for d in $sources; do
  grep -qx "$d" <<<"$named" || { echo "source folder '$d' is missing from docs/layout.md's table"; fail=1; }
  mirror=tests/${d#src/}
  [ -d "$mirror" ] || { echo "source folder '$d' has no test folder '$mirror'"; fail=1; }
done
for t in $tests; do
  covered=0
  for n in $named; do [ "$t" = "$n" ] || [ "${t#"$n"/}" != "$t" ] && covered=1; done  # named, or inside a named folder
  for d in $sources; do [ "$t" = "tests/${d#src/}" ] && covered=1; done
  [ $covered = 1 ] || { echo "test folder '$t' is neither a mirror of a source folder nor in docs/layout.md's table"; fail=1; }
done
[ $fail = 0 ] && echo "docs/layout.md table matches the tree ($(wc -w <<<"$sources") source folders, $(wc -w <<<"$tests") test folders)"
exit $fail
