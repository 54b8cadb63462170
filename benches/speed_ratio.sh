#!/usr/bin/env bash
# The render time of two raytree binaries in one run, as a ratio (issue 28: a restructuring must
# keep the speed within 2%). Each case renders with both binaries alternately, REPS times, and
# the fastest wall time of each counts (the least disturbed run). Not run by CI.
# Usage: benches/speed_ratio.sh OLD_BINARY NEW_BINARY [REPS]
set -eu
old=$1
new=$2
reps=${3:-5}
cd "$(dirname "$0")/.."
out=$(mktemp -d)
cases=(
  "classic (Whitted, glass)|fixtures/classic.json --size 480x270"
  "diffuse (direct-only path)|fixtures/diffuse.json --size 480x270"
  "soft-shadows (area lights)|fixtures/soft-shadows.json"
  "glossy (rough lobes)|fixtures/glossy.json"
  "cornell-box (path, 16 spp)|fixtures/cornell-box.json --integrator path --spp 16"
  "caustic (path, 16 spp)|fixtures/caustic.json --integrator path --spp 16"
)
[ -d ../shared/data/meshes ] && cases+=("bunny (mesh packets)|fixtures/mesh/bunny.json")
best() { # binary args... -> fastest wall seconds over one run
  local b=$1; shift
  local t0 t1
  t0=$(date +%s.%N)
  # shellcheck disable=SC2068
  "$b" render $@ -o "$out/x.exr" >/dev/null 2>&1
  t1=$(date +%s.%N)
  echo "$t1 - $t0" | bc -l
}
printf "%-30s %10s %10s %8s\n" case old_s new_s new/old
for c in "${cases[@]}"; do
  name=${c%%|*}; args=${c#*|}
  bo=1e9; bn=1e9
  for _ in $(seq "$reps"); do
    to=$(best "$old" $args); tn=$(best "$new" $args)
    bo=$(echo "if ($to < $bo) $to else $bo" | bc -l)
    bn=$(echo "if ($tn < $bn) $tn else $bn" | bc -l)
  done
  printf "%-30s %10.3f %10.3f %8.3f\n" "$name" "$bo" "$bn" "$(echo "$bn / $bo" | bc -l)"
done
rm -rf "$out"
