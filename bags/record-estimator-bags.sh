#!/usr/bin/env bash
# Records the estimator reference bags bags/estimator-<profile>-40s/ (see bags/README.md):
# the `estimator` scene (UAV surrogate, default faults) for 40 s of each profile, the sensors
# seeded per profile (jonswap 1, hpr1 2, hpr2 3, hpr3 4, still 5: independent noise and faults),
# keeping only what the estimator consumes and is scored against (IMUs, dGPS fixes, truth,
# injected faults). The nodes run in lockstep, so the bags do not depend on machine load.
# Usage: bags/record-estimator-bags.sh [PROFILE...]   (default: jonswap hpr1 hpr2 hpr3 still)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
profiles=("$@")
[ ${#profiles[@]} -gt 0 ] || profiles=(jonswap hpr1 hpr2 hpr3 still)
declare -A seeds=([jonswap]=1 [hpr1]=2 [hpr2]=3 [hpr3]=4 [still]=5)
for profile in "${profiles[@]}"; do
  name="estimator-$profile-40s"
  sed -e "s/profile: hpr3/profile: $profile/" -e "s/{truth: surrogate, seed: 3}/{truth: surrogate, seed: ${seeds[$profile]}}/" \
    "$root/src/tether_bringup/scenes/estimator.yaml" > "$work/$name.yaml"
  grep -q "seed: ${seeds[$profile]}}" "$work/$name.yaml"
  printf 'record:\n  exclude: [/rosout, /parameter_events, /clock, /platform/imu, /platform/reel_pose, %s]\n' \
    '/platform/reel_twist, /platform/state, /estimate/relative, /estimate/foh, /estimate/rejections' \
    >> "$work/$name.yaml"
  "$root/tethersim" run "$work/$name.yaml" --duration 40 --rate max --out "$work/$name"
  rm -rf "${here:?}/$name"
  mkdir "$here/$name"
  cp "$work/$name/bag/bag_0.mcap" "$here/$name/${name}_0.mcap"
  sed -e "s/bag_0\.mcap/${name}_0.mcap/g" "$work/$name/bag/metadata.yaml" > "$here/$name/metadata.yaml"
done
