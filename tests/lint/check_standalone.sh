#!/usr/bin/env bash
# Fails when a file of the repository, other than this script, refers to a path in a shared/
# folder beside the repository (dot-dot-slash shared): the repository must stand alone (the
# scene is in assets/, the design in docs/). In a git checkout it searches the tracked files
# (git grep); in a tree that is not one (an export, a tarball) a plain grep over the tree,
# leaving out build trees, out/ and node_modules/ as .gitignore does.
# Usage: check_standalone.sh SOURCE_DIR
set -euo pipefail

root="$(cd "$1" && pwd -P)"
self="tests/lint/check_standalone.sh"
pattern='\.\./shared'

status=0
if [[ "$(git -C "$root" rev-parse --show-toplevel 2>/dev/null)" == "$root" ]]; then
  hits="$(git -C "$root" grep -n -I -e "$pattern" -- . ":(exclude)$self")" || status=$?
else
  echo "check_standalone: $root is not a git checkout; searching its files with grep"
  hits="$(cd "$root" && grep -rnI --exclude-dir=.git --exclude-dir='build*' --exclude-dir=out \
    --exclude-dir=node_modules --exclude="${self##*/}" -e "$pattern" .)" || status=$?
fi
# git grep and grep: 0 found, 1 none, more: could not search.
((status <= 1)) || { echo "check_standalone: the search failed ($status)" >&2; exit 1; }
if [[ -n "$hits" ]]; then
  echo "check_standalone: these refer to a shared/ folder beside the repository:" >&2
  echo "$hits" >&2
  exit 1
fi
echo "check_standalone: no file refers to a shared/ folder beside the repository"
