#!/usr/bin/env bash
# tools/check-format on a scratch git checkout: passes on formatted files, fails naming the file
# that is not, and passes again once it is formatted.
set -euo pipefail
root=$1
check="$root/tools/check-format"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$root/.clang-format" "$tmp/"
mkdir -p "$tmp/src"
printf 'int Add(int a, int b) { return a + b; }\n' > "$tmp/src/good.cc"
git -C "$tmp" init -q
git -C "$tmp" add -A
"$check" "$tmp" || { echo "FAIL: a formatted tree was refused"; exit 1; }
printf 'int   Sub( int a,int b ){return a-b;}\n' > "$tmp/src/bad.cc"
git -C "$tmp" add -A
if out=$("$check" "$tmp" 2>&1); then echo "FAIL: an unformatted file passed"; exit 1; fi
grep -q "src/bad.cc" <<<"$out" || { echo "FAIL: the file is not named: $out"; exit 1; }
grep -q "src/good.cc" <<<"$out" && { echo "FAIL: a formatted file is named: $out"; exit 1; }
clang-format -i "$tmp/src/bad.cc"
"$check" "$tmp" || { echo "FAIL: refused after formatting"; exit 1; }
echo "format check test passed"
