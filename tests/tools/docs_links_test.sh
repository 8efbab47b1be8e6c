#!/usr/bin/env bash
# README.md and docs/*.md: every relative link resolves (the file exists; a #fragment names a
# heading of the page, as GitHub makes its anchor), and every page of docs/ is linked from
# README. `docs_links_test.sh SRC`.
set -euo pipefail
export LC_ALL=C.UTF-8
cd "$1"

# GitHub's anchor of a heading: lower case, punctuation and symbols dropped, spaces to '-'.
anchors() { grep -E '^#{1,6} ' "$1" | sed -E 's/^#+ +//' | tr '[:upper:]' '[:lower:]' | sed -E 's/[^[:alnum:] _-]//g; s/ /-/g'; }

fail=0 links=0
for page in README.md docs/*.md; do
  dir=$(dirname "$page")
  while IFS= read -r target; do
    case "$target" in http://* | https://* | mailto:*) continue ;; esac
    links=$((links + 1))
    path=${target%%#*}
    frag=""
    [ "$path" != "$target" ] && frag=${target#*#}
    file=$page
    [ -n "$path" ] && file=$dir/$path
    if [ ! -e "$file" ]; then
      echo "$page: link to '$target': no such file ($file)"
      fail=1
      continue
    fi
    if [ -n "$frag" ] && [[ "$file" == *.md ]] && ! anchors "$file" | grep -qxF -- "$frag"; then
      echo "$page: link to '$target': no heading of $file has the anchor '#$frag'"
      fail=1
    fi
  done < <(grep -oE '\]\([^)[:space:]]+\)' "$page" | sed -E 's/^\]\(//; s/\)$//')
done
for page in docs/*.md; do
  grep -qF "]($page" README.md || { echo "docs page $page is not linked from README.md"; fail=1; }
done
lines=$(wc -l <README.md)
[ "$lines" -le 250 ] || { echo "README.md has $lines lines; at most 250 (the rest belongs in docs/)"; fail=1; }
[ $fail = 0 ] && echo "README.md ($lines lines) and $(ls docs/*.md | wc -l) docs pages: $links relative links, all resolve"
exit $fail
