#!/usr/bin/env bash
# Builds the meshd image with podman on a machine like ours (see ../shared/CONTAINERS.md):
# installs podman when missing, makes the local Debian base image with debootstrap when it
# is missing (no registry is reachable), then builds docker/Dockerfile as localhost/meshd.
# Usage: docker/build.sh [tag]
set -euo pipefail
cd "$(dirname "$0")/.."
tag="${1:-localhost/meshd:latest}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo=sudo

need=()
for p in podman runc debootstrap uidmap; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}"
fi

# podman on these machines: runc (crun refuses the hybrid cgroups), cgroupfs, lower ulimits.
conf=/etc/containers/containers.conf
if ! grep -q '^runtime = "runc"' "$conf" 2>/dev/null; then
  $sudo mkdir -p /etc/containers
  $sudo tee "$conf" >/dev/null <<'CONF'
[containers]
default_ulimits = ["nofile=20000:20000", "nproc=32768:32768"]

[engine]
runtime = "runc"
cgroup_manager = "cgroupfs"
events_logger = "file"
CONF
fi

if ! $sudo podman image exists docker.io/library/debian:bookworm; then
  # The mirror apt already uses (deb822 "URIs:" or one-line "deb" entries, not comments).
  mirror=$(grep -h -E '^(URIs:|deb )' /etc/apt/sources.list /etc/apt/sources.list.d/* 2>/dev/null \
           | grep -o 'http[s]*://[^ ]*' | grep -v security | head -1 || true)
  mirror="${mirror:-http://deb.debian.org/debian}"
  rootfs=$(mktemp -d)
  echo "making the base image from $mirror"
  $sudo debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >/dev/null
  $sudo tar -C "$rootfs" -c . | $sudo podman import - localhost/debian:bookworm >/dev/null
  $sudo podman tag localhost/debian:bookworm docker.io/library/debian:bookworm
  $sudo rm -rf "$rootfs"
fi

$sudo podman build --pull=never --format docker -f docker/Dockerfile -t "$tag" .
$sudo podman image inspect "$tag" --format '{{.Size}}' | awk '{ printf "image size: %.1f MB\n", $1 / 1e6 }'
