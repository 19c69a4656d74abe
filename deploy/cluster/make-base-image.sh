#!/usr/bin/env bash
# Makes the Debian bookworm base image the cluster's images build on, without Docker Hub:
# debootstrap a minimal bookworm into a folder, `docker import` it as mbstream-base:bookworm.
#
#   deploy/cluster/make-base-image.sh [--mirror URL] [--tag NAME]
#
#   --mirror  the Debian mirror debootstrap fetches from; default: the first bookworm "URIs:"
#             (deb822) or "deb" line of this machine's own APT sources, so that the image
#             uses the mirror the host already reaches
#   --tag     image name (default mbstream-base:bookworm)
#
# Needs root, debootstrap and a running Docker daemon. The image's APT sources are the same
# mirror, so `apt-get install` works in `docker build --network host`.
set -euo pipefail

tag=mbstream-base:bookworm
mirror=""
while [ $# -gt 0 ]; do
  case "$1" in
    --mirror) mirror=$2; shift 2 ;;
    --tag) tag=$2; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "make-base-image: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ "$(id -u)" -eq 0 ] || { echo "make-base-image: debootstrap needs root" >&2; exit 1; }
command -v debootstrap >/dev/null || { echo "make-base-image: apt-get install debootstrap" >&2; exit 1; }
docker info >/dev/null 2>&1 || { echo "make-base-image: no Docker daemon answers (deploy/cluster/start-dockerd.sh)" >&2; exit 1; }

if [ -z "$mirror" ]; then
  mirror=$(grep -h -m1 -E '^URIs:' /etc/apt/sources.list.d/*.sources 2>/dev/null | awk '{print $2}' | head -n1 || true)
  [ -n "$mirror" ] || mirror=$(grep -h -m1 -E '^deb ' /etc/apt/sources.list 2>/dev/null | awk '{print $2}' | head -n1 || true)
  [ -n "$mirror" ] || { echo "make-base-image: no APT source found; give --mirror URL" >&2; exit 1; }
fi

root=$(mktemp -d /tmp/mbstream-base.XXXXXX)
trap 'rm -rf "$root"' EXIT
echo "make-base-image: debootstrap --variant=minbase bookworm from $mirror"
debootstrap --variant=minbase --include=ca-certificates bookworm "$root" "$mirror" >"$root.log" 2>&1 ||
  { tail -n 20 "$root.log" >&2; exit 1; }
rm -f "$root.log"
echo "deb $mirror bookworm main" >"$root/etc/apt/sources.list"
rm -rf "$root"/var/cache/apt/archives/*.deb "$root"/var/lib/apt/lists/*
tar -C "$root" -c . | docker import - "$tag" >/dev/null
echo "make-base-image: imported $tag ($(docker image inspect -f '{{.Size}}' "$tag") bytes)"
