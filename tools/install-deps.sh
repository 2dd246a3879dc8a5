#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages rt64k needs, only those missing.
# Usage: tools/install-deps.sh [build|test|intro]   (default: test = everything)
set -euo pipefail
what=${1:-test}
native=(g++ cmake make pkg-config libpng-dev libgtest-dev gnuplot-nox python3)
windows=(g++-mingw-w64-x86-64 wine wine64 xvfb xdotool x11-utils imagemagick pulseaudio pulseaudio-utils)
case "$what" in
  build) pkgs=("${native[@]}") ;;
  intro) pkgs=(cmake make g++ libpng-dev "${windows[@]}") ;;
  test) pkgs=("${native[@]}" "${windows[@]}") ;;
  *) echo "install-deps.sh: unknown set '$what' (build, test or intro)" >&2; exit 2 ;;
esac
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps.sh: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo=sudo
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
