#!/bin/sh
# The baseline binary of `make bench`, built beside the working tree.
#
# Usage: scripts/bench_baseline.sh [COMMIT]
#
# COMMIT defaults to the merge-base of HEAD with origin/main (with main when there is no
# origin). Its tree is exported with `git archive` into target/bench-baseline/<sha>/src and built
# there in release with its own target directory, target/bench-baseline/target, seeded with the
# working tree's compiled dependencies (target/release/deps, build, .fingerprint) so that only
# the crate itself is compiled when Cargo.lock is unchanged. The binary is kept as
# target/bench-baseline/<sha>/signorini and reused by the next run. When the working tree's
# tracked files are the commit's, the working tree's own binary is copied instead of building it
# again. Prints the binary's path and the full commit id, separated by a space.
set -eu
root=$(git rev-parse --show-toplevel)
cd "$root"
if [ $# -ge 1 ] && [ -n "$1" ]; then
  commit=$1
elif git rev-parse --verify -q origin/main >/dev/null; then
  commit=$(git merge-base HEAD origin/main)
else
  commit=$(git merge-base HEAD main)
fi
sha=$(git rev-parse --verify "$commit^{commit}")
dir=target/bench-baseline/$sha
bin=$dir/signorini
if [ ! -x "$bin" ]; then
  mkdir -p "$dir"
  if git diff --quiet "$sha" -- && [ -x target/release/signorini ]; then
    echo "baseline $sha is the working tree: its binary is copied" >&2
    cp target/release/signorini "$bin.tmp"
  else
    echo "building the baseline $sha in $dir/src (target/bench-baseline/target)" >&2
    rm -rf "$dir/src"
    mkdir -p "$dir/src" target/bench-baseline/target/release
    # Extracted with the time of extraction (-m), and without the crate's own build state,
    # so that the crate is compiled from the commit's sources and never taken for up to date.
    git archive "$sha" | tar -x -m -C "$dir/src"
    for part in deps build .fingerprint; do
      if [ -d "target/release/$part" ] && [ ! -d "target/bench-baseline/target/release/$part" ]; then
        cp -a "target/release/$part" "target/bench-baseline/target/release/"
      fi
    done
    rm -rf target/bench-baseline/target/release/.fingerprint/signorini-* \
      target/bench-baseline/target/release/deps/signorini-* \
      target/bench-baseline/target/release/deps/libsignorini-* \
      target/bench-baseline/target/release/build/signorini-*
    (cd "$dir/src" && CARGO_TARGET_DIR="$root/target/bench-baseline/target" cargo build --release --bin signorini >&2)
    cp target/bench-baseline/target/release/signorini "$bin.tmp"
    rm -rf "$dir/src"
  fi
  mv "$bin.tmp" "$bin"
fi
echo "$bin $sha"
