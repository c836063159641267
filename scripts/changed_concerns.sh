#!/usr/bin/env bash
# The test concerns (tests/<concern>/ with serial test files) whose code changed most lately,
# as a CMake list: the sanitized slice of CI builds and runs their serial test programs whole
# (scripts/test_sanitized.sh, docs/reliability.md, "Sanitizers").
# Usage: scripts/changed_concerns.sh [COUNT [WINDOW]]   (3 concerns, the last 100 commits)
#
# First the concerns of the newest commit's change (against its first parent, so a merge
# counts as its whole branch), then those the most of the last WINDOW commits touched (ties
# by name), COUNT in all. A concern's code: src/<concern>/ and tests/<concern>/; solvers/
# and src/verification/ are the solvers' (test_solvers). src/common/ counts for none (every
# concern uses it, and the tests that always run go through it), nor app/ and cuda/ (the
# slice runs their tests always). Prints "all" where the history is not there to read (no
# git, a tree that is not a clone of its own, a shallow clone with fewer commits than WINDOW):
# then every serial test program.
set -euo pipefail
cd "$(dirname "$0")/.."
COUNT=${1:-3}
WINDOW=${2:-100}

concerns=$(find tests -mindepth 2 -maxdepth 2 -name 'test_*.cpp' | cut -d/ -f2 | sort -u |
  grep -vx app | tr '\n' ' ')
if [ "$(git rev-parse --show-toplevel 2> /dev/null)" != "$(pwd -P)" ] ||
  ! commits=$(git rev-list --count HEAD 2> /dev/null) ||
  { [ "$(git rev-parse --is-shallow-repository)" = true ] && ((commits < WINDOW)); }; then
  echo all
  exit 0
fi

# Reads "@" (a commit's start) and the paths it touched; prints each concern with the
# number of commits that touched it.
count_concerns() {
  awk -v concerns="$concerns" '
    BEGIN { n = split(concerns, list, " "); for (i = 1; i <= n; i++) known[list[i]] = 1 }
    /^@/ { for (c in seen) delete seen[c]; next }
    NF {
      split($0, part, "/")
      c = ""
      if ((part[1] == "src" || part[1] == "tests") && (part[2] in known)) c = part[2]
      else if (part[1] == "solvers" || (part[1] == "src" && part[2] == "verification")) c = "solvers"
      if (c != "" && !(c in seen)) { seen[c] = 1; touched[c]++ }
    }
    END { for (c in touched) print touched[c], c }'
}

newest=$( (echo @ && git diff --name-only HEAD^1 HEAD 2> /dev/null || true) | count_concerns |
  awk '{print $2}')
window=$(git log -n "$WINDOW" --format=@%h --name-only | count_concerns)
# The newest change's concerns rank first (1), then the window's counts, more first.
chosen=$(echo "$window" | awk -v newest="$newest" '
    BEGIN { n = split(newest, list, " "); for (i = 1; i <= n; i++) first[list[i]] = 1 }
    NF { print ($2 in first) ? 1 : 2, $1, $2 }' |
  sort -k1,1n -k2,2nr -k3,3 | head -n "$COUNT" | awk '{print $3}' | sort)
echo "$chosen" | paste -sd ';'
