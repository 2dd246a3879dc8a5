#!/bin/bash
# wine.memory: 60 s of the running intro without memory growth. The wine
# process's resident set (VmRSS) is sampled every second. The first
# kWarmupSeconds are start-up (Wine loading DLLs, the first frames touching
# the framebuffer and stacks); after that, no sample may exceed the one at
# the end of the warm-up by more than kMaxGrowthKiB. The intro allocates
# everything once, before the first frame (measured: VmRSS flat to the KiB
# from the first sample on), so any growth is a per-frame leak: at the
# ~40 fps of the adaptive renderer on 2 cores, 50 s are ~2,000 frames, and
# 256 KiB catches a leak of 128 bytes per frame (a GDI object or a heap block
# per frame is more).
source "$(dirname "$0")/common.sh"
readonly kRunSeconds=60
readonly kWarmupSeconds=10
readonly kMaxGrowthKiB=256
setup
launch_intro
wait_window
samples=()
for i in $(seq $kRunSeconds); do
  sleep 1
  kib=$(rss_kib)
  [ -n "$kib" ] && intro_running || fail "intro.exe ended after ${i} s"
  samples+=("$kib")
done
base=${samples[$((kWarmupSeconds - 1))]}
max=$base
for kib in "${samples[@]:$kWarmupSeconds}"; do [ "$kib" -gt "$max" ] && max=$kib; done
echo "VmRSS (KiB) each second: ${samples[*]}"
echo "after ${kWarmupSeconds} s: $base KiB; max over the remaining $((kRunSeconds - kWarmupSeconds)) s:" \
  "$max KiB; growth $((max - base)) KiB (limit $kMaxGrowthKiB KiB)"
[ $((max - base)) -le $kMaxGrowthKiB ] || fail "memory grew by $((max - base)) KiB"
escape_exits_cleanly
echo "PASS"
