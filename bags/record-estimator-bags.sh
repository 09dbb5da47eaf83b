#!/usr/bin/env bash
# Records the estimator reference bags bags/estimator-<profile>-40s/ (see bags/README.md):
# the `estimator` scene (UAV surrogate, default faults, seed 3) for 40 s of each profile,
# keeping only the sensor, truth and estimate topics.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for profile in jonswap hpr1 hpr2 hpr3 still; do
  name="estimator-$profile-40s"
  sed -e "s/profile: hpr3/profile: $profile/" "$root/src/tether_bringup/scenes/estimator.yaml" > "$work/$name.yaml"
  printf 'record:\n  exclude: [/rosout, /parameter_events, /platform/imu, /platform/reel_pose, /platform/state]\n' \
    >> "$work/$name.yaml"
  "$root/tethersim" run "$work/$name.yaml" --duration 40 --rate 2 --out "$work/$name"
  rm -rf "${here:?}/$name"
  mkdir "$here/$name"
  cp "$work/$name/bag/bag_0.mcap" "$here/$name/${name}_0.mcap"
  sed -e "s/bag_0\.mcap/${name}_0.mcap/g" "$work/$name/bag/metadata.yaml" > "$here/$name/metadata.yaml"
done
