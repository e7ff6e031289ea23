#!/usr/bin/env bash
# Tests tools/check-layering on a scratch tree: a few of the project's own files copied into a
# temporary folder pass; each bad include added to them fails the check with its file and line.
#   tests/tools/layering_check_test.sh [REPO]      (REPO: the repository, by default)
set -euo pipefail
repo=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
check="$repo/tools/check-layering"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# The scratch tree: one or two files of tracking, dynamics, core, pipeline and cli.
for f in tracking/pose.h tracking/pose.cc dynamics/parameters.h src/core/frames.h \
         src/pipeline/trial_analysis.h src/cli/commands.h src/cli/main.cc; do
  mkdir -p "$scratch/$(dirname "$f")"
  cp "$repo/$f" "$scratch/$f"
done

# run_check: runs the check on the scratch tree; sets $out and $rc.
run_check() {
  set +e
  out=$("$check" "$scratch" 2>&1)
  rc=$?
  set -e
}

# expect_line FILE LINE A B INCLUDE: the output holds exactly that violation.
expect_line() {
  local want="$1:$2: module $3 may not include module $4 (\"$5\")"
  grep -qxF "$want" <<<"$out" || fail "expected the line: $want
got:
$out"
}

# add_include FILE INCLUDE: appends `#include "INCLUDE"` to FILE; echoes its line number.
add_include() {
  echo "#include \"$2\"" >>"$scratch/$1"
  wc -l <"$scratch/$1"
}

# 1. The clean tree passes and prints nothing.
run_check
[ "$rc" -eq 0 ] || fail "clean tree: exit $rc, expected 0; output: $out"
[ -z "$out" ] || fail "clean tree: expected no output, got: $out"

# 2. tracking includes cli/ and dynamics/: exit 1, each named with its file and line.
line_cli=$(add_include tracking/pose.h cli/commands.h)
line_dyn=$(add_include tracking/pose.h dynamics/parameters.h)
run_check
[ "$rc" -eq 1 ] || fail "bad includes in tracking: exit $rc, expected 1"
expect_line tracking/pose.h "$line_cli" tracking cli cli/commands.h
expect_line tracking/pose.h "$line_dyn" tracking dynamics dynamics/parameters.h
[ "$(wc -l <<<"$out")" -eq 2 ] || fail "expected 2 violations, got: $out"
cp "$repo/tracking/pose.h" "$scratch/tracking/pose.h"

# 3. dynamics includes tracking/ (the other direction), from a .h.
line=$(add_include dynamics/parameters.h tracking/pose.h)
run_check
[ "$rc" -eq 1 ] || fail "dynamics -> tracking: exit $rc, expected 1"
expect_line dynamics/parameters.h "$line" dynamics tracking tracking/pose.h
cp "$repo/dynamics/parameters.h" "$scratch/dynamics/parameters.h"

# 4. core includes another module; pipeline includes cli/ by a relative path; a library
#    includes the tests' helpers and a benchmark.
line_core=$(add_include src/core/frames.h pipeline/trial_analysis.h)
line_rel=$(add_include src/pipeline/trial_analysis.h ../cli/commands.h)
line_support=$(add_include tracking/pose.cc support/run_command.h)
line_bench=$(add_include tracking/pose.cc bench/x.h)
run_check
[ "$rc" -eq 1 ] || fail "core, relative, tests and bench includes: exit $rc, expected 1"
expect_line src/core/frames.h "$line_core" core pipeline pipeline/trial_analysis.h
expect_line src/pipeline/trial_analysis.h "$line_rel" pipeline cli ../cli/commands.h
expect_line tracking/pose.cc "$line_support" tracking tests support/run_command.h
expect_line tracking/pose.cc "$line_bench" tracking bench bench/x.h
for f in src/core/frames.h src/pipeline/trial_analysis.h tracking/pose.cc; do cp "$repo/$f" "$scratch/$f"; done

# 5. The program may include cli/ and the libraries it links.
add_include src/cli/main.cc cli/commands.h >/dev/null
add_include src/cli/main.cc pipeline/trial_analysis.h >/dev/null
run_check
[ "$rc" -eq 0 ] || fail "cli including cli/ and pipeline/: exit $rc, expected 0; output: $out"

# 6. synth may include tracking's camera-file header and no other header of tracking.
mkdir -p "$scratch/src/synth"
echo '#include "tracking/camera_file.h"' >"$scratch/src/synth/writer.cc"
run_check
[ "$rc" -eq 0 ] || fail "synth including tracking/camera_file.h: exit $rc, expected 0; output: $out"
line=$(add_include src/synth/writer.cc tracking/pose.h)
run_check
[ "$rc" -eq 1 ] || fail "synth -> tracking/pose.h: exit $rc, expected 1"
want="src/synth/writer.cc:$line: module synth may include only tracking/camera_file.h of module tracking (\"tracking/pose.h\")"
grep -qxF "$want" <<<"$out" || fail "expected the line: $want
got:
$out"
rm -r "$scratch/src/synth"

# 7. A module that is not in the table is an error (exit 2), not a silent pass.
mkdir -p "$scratch/src/newmodule"
echo '#include "cli/commands.h"' >"$scratch/src/newmodule/a.cc"
run_check
[ "$rc" -eq 2 ] || fail "a module missing from the table: exit $rc, expected 2"
grep -q "src/newmodule is not in the table" <<<"$out" || fail "a module missing from the table: got: $out"

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "layering check test: all cases passed"
