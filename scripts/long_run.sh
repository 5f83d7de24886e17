#!/usr/bin/env bash
# A long run with its memory measured (issue 7): a rendered sequence played back and forth until
# it is N frames long (default 10,000), run through each back-end while the resident memory is
# sampled against the number of frames done. Memory must stay flat: nothing per frame may grow
# with the sequence length.
#
#   scripts/long_run.sh [--frames N] [--sequence DIR] [--out DIR]
#
# Without --sequence it renders tv1. Writes OUT/memory_<method>.csv (seconds, frames done, RSS kB)
# and prints a table of RSS at 10 %, 50 % and 100 % of the run.
set -euo pipefail
cd "$(dirname "$0")/.."

frames=10000
sequence=""
out="long_run"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --frames) frames="$2"; shift 2 ;;
    --sequence) sequence="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "long_run.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

[[ -x build/eval/slamcmp ]] || ./scripts/build.sh
slamcmp="$PWD/build/eval/slamcmp"
mkdir -p "$out"
out="$(cd "$out" && pwd)"

if [[ -z "$sequence" ]]; then
  sequence="$out/tv1"
  [[ -f "$sequence/rgb.txt" ]] || "$slamcmp" synth --preset tv1 --out "$sequence"
fi
sequence="$(cd "$sequence" && pwd)"

# The long sequence: the source's frames forwards, then backwards, and so on (the motion stays
# continuous), with timestamps that keep increasing at the source's frame interval.
long="$out/long_sequence"
mkdir -p "$long"
cp "$sequence/camera.yaml" "$sequence/target.yaml" "$long/"
python3 - "$sequence" "$long" "$frames" <<'EOF'
import os, sys
src, dst, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
def rows(name):
    with open(os.path.join(src, name)) as f:
        return [l.split() for l in f if l.strip() and not l.startswith('#')]
images, poses = rows('rgb.txt'), rows('groundtruth.txt')
assert len(images) == len(poses) and len(images) > 1, 'rgb.txt and groundtruth.txt must pair up'
dt = (float(images[-1][0]) - float(images[0][0])) / (len(images) - 1)
cycle = list(range(len(images))) + list(range(len(images) - 2, 0, -1))
with open(os.path.join(dst, 'rgb.txt'), 'w') as rgb, \
     open(os.path.join(dst, 'groundtruth.txt'), 'w') as gt:
    rgb.write('# %d frames played back and forth from %s\n' % (n, src))
    gt.write('# timestamp tx ty tz qx qy qz qw (T_world_camera)\n')
    for k in range(n):
        i = cycle[k % len(cycle)]
        t = '%.6f' % (k * dt)
        rgb.write('%s %s\n' % (t, os.path.join(src, images[i][1])))
        gt.write('%s %s\n' % (t, ' '.join(poses[i][1:])))
EOF

# Runs one method, sampling VmRSS twice a second against the frames done so far.
measure() {
  local name="$1"; shift
  local run_dir="$out/run_$name" csv="$out/memory_$name.csv"
  rm -rf "$run_dir"
  "$slamcmp" run --sequence "$long" --out "$run_dir" "$@" >/dev/null 2>"$out/run_$name.log" &
  local pid=$! start=$SECONDS
  echo "seconds,frames,rss_kb" >"$csv"
  while kill -0 "$pid" 2>/dev/null; do
    local rss done_frames
    rss=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
    done_frames=0
    [[ -f "$run_dir/frames.csv" ]] && done_frames=$(($(wc -l <"$run_dir/frames.csv") - 1))
    [[ -n "$rss" ]] && echo "$((SECONDS - start)),$done_frames,$rss" >>"$csv"
    sleep 0.5
  done
  wait "$pid" || { echo "long_run.sh: $name failed, see $out/run_$name.log" >&2; exit 1; }
  python3 - "$csv" "$name" "$frames" "$run_dir/summary.json" <<'EOF'
import csv, json, sys
path, name, n, summary = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
rows = [(int(r['frames']), int(r['rss_kb'])) for r in csv.DictReader(open(path))]
def rss_at(share):
    target = share * n
    return min(rows, key=lambda r: abs(r[0] - target))[1] / 1024
s = json.load(open(summary))
print('| %s | %d/%d | %.1f | %.1f | %.1f | %.1f |' % (
    name, s['tracked'], s['frames'], rss_at(0.1), rss_at(0.5), rss_at(1.0),
    max(r[1] for r in rows) / 1024))
EOF
}

echo "| method | tracked | RSS at 10 % [MiB] | at 50 % | at 100 % | max |"
echo "|---|---|---|---|---|---|"
measure cslam --backend cslam
measure cslam_two_view --backend cslam --mode two_view
measure monoslam --backend monoslam
