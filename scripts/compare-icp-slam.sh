#!/usr/bin/env bash
# SLAM accuracy side by side: asf and MRPT's icp-slam (its Levenberg-Marquardt demo config).
#   scripts/compare-icp-slam.sh [--set carmen|simulated] [--seeds "1 2 3"]
#                               [--config INI] [--asf-set KEY=VALUE]... [--logs DIR]
#                               [--no-icp-slam] [WORK_DIR]
# carmen (default): every *.log.gz in DIR (default ../shared/datasets/carmen), converted for
#   each seed with `asf carmen2rawlog --synth-odometry --seed S` (the corrected poses are the
#   ground truth), run three ways: odometry only (configs/replay_rawlog.ini), asf (INI,
#   default configs/slam_carmen.ini), icp-slam. Prints a markdown table: ATE RMSE per seed
#   (`asf ate`, after SE(2) alignment; asf and odometry: final keyframe poses, icp-slam: every
#   scan's pose) and the median frames per second over the seeds (scans / wall time).
# simulated: configs/slam_simul.ini and slam_simul_noisy.ini on MRPT's two simulated
#   graphslam-engine logs with ground truth.
# --asf-set passes `--set KEY=VALUE` to asf's SLAM runs (carmen), e.g.
# --asf-set sparse_lm.robust_kernel=dcs. --no-icp-slam (carmen) leaves icp-slam out: for trying asf configurations (icp-slam's
# results do not change). Needs the built host (scripts/build.sh) and icp-slam (Debian
# package mrpt-apps). Runs one program at a time; outputs in WORK_DIR (default
# results/compare-icp-slam).
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF:-build/bin/asf}
SET=carmen SEEDS="1 2 3" CONFIG=configs/slam_carmen.ini LOG_DIR=../shared/datasets/carmen
ICP=1 ASF_SETS=()
while (($#)); do
  case $1 in
    --set) SET=$2; shift 2 ;;
    --seeds) SEEDS=$2; shift 2 ;;
    --config) CONFIG=$2; shift 2 ;;
    --logs) LOG_DIR=$2; shift 2 ;;
    --no-icp-slam) ICP=0; shift ;;
    --asf-set) ASF_SETS+=(--set "$2"); shift 2 ;;
    -*) echo "compare-icp-slam: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
WORK=${1:-results/compare-icp-slam}
LOGS=/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map
ICP_INI=/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_LM.ini
[[ -x "$ASF" ]] || { echo "compare-icp-slam: $ASF not built (run scripts/build.sh)" >&2; exit 2; }
if ((ICP)); then
  command -v icp-slam >/dev/null || {
    echo "compare-icp-slam: icp-slam not found (apt-get install mrpt-apps)" >&2; exit 2; }
  [[ -f "$ICP_INI" ]] || {
    echo "compare-icp-slam: MRPT's icp-slam config missing (apt-get install mrpt-apps)" >&2; exit 2; }
fi
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)

now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
seconds() { local ms=$(( $(now_ms) - $1 )); printf "%d.%03d" $((ms / 1000)) $((ms % 1000)); }
ate() { "$ASF" ate "$@" --json | sed -n 's/.*"ate_rmse_m": \([0-9.e-]*\).*/\1/p'; }
# icp-slam's config for RAWLOG with outputs in DIR.
icp_ini() {
  sed -e "s|^rawlog_file\s*=.*|rawlog_file=$1|" \
      -e "s|^logOutput_dir\s*=.*|logOutput_dir=$2|" \
      -e "s|^SHOW_PROGRESS_3D_REAL_TIME\s*=.*|SHOW_PROGRESS_3D_REAL_TIME=false|" \
      -e "s|^SAVE_3D_SCENE\s*=.*|SAVE_3D_SCENE=0|" "$ICP_INI"
}
median() {
  tr ' ' '\n' | grep -v '^$' | sort -g | awk '{v[NR]=$1} END{print NR ? v[int((NR+1)/2)] : "-"}'
}
# "a / b / c" with three decimals ("-" stays).
ates() { local out="" v; for v in "$@"; do [[ $v == - ]] || v=$(printf '%.3f' "$v"); out+="${out:+ / }$v"; done; echo "$out"; }

compare_carmen() {
  [[ -d "$LOG_DIR" ]] || { echo "compare-icp-slam: no CARMEN logs in $LOG_DIR" >&2; exit 2; }
  [[ -f "$CONFIG" ]] || { echo "compare-icp-slam: no config $CONFIG" >&2; exit 2; }
  echo "| log | scans | odometry ATE [m] | asf ATE [m] | icp-slam ATE [m] | asf fps | icp-slam fps |"
  echo "|---|---|---|---|---|---|---|"
  for log in "$LOG_DIR"/*.log.gz; do
    local name a_odo="" a_asf="" a_icp="" f_asf="" f_icp="" scans=0
    name=$(basename "$log" .log.gz)
    name=${name%-corrected}
    for seed in $SEEDS; do
      local base="$WORK/$name-s$seed" t0 t
      echo "compare-icp-slam: $name seed $seed" >&2
      "$ASF" carmen2rawlog -q --synth-odometry --seed "$seed" -i "$log" -o "$base.rawlog.gz" \
        --gt "$base.gt.txt" > "$base.convert.log" 2>&1
      scans=$(sed -n 's/^carmen2rawlog: \([0-9]*\) scans.*/\1/p' "$base.convert.log")
      "$ASF" run configs/replay_rawlog.ini -o "$base-odometry" --set pipeline.progress_interval=0 \
        --set rawlog.file="$base.rawlog.gz" --set rawlog.ground_truth="$base.gt.txt" \
        > "$base-odometry.log" 2>&1
      a_odo+=" $(ate "$base-odometry/keyframes.txt" "$base.gt.txt")"
      t0=$(now_ms)
      "$ASF" run "$CONFIG" -o "$base-asf" --set pipeline.progress_interval=0 \
        --set rawlog.file="$base.rawlog.gz" --set rawlog.ground_truth="$base.gt.txt" \
        ${ASF_SETS[@]+"${ASF_SETS[@]}"} > "$base-asf.log" 2>&1
      t=$(seconds "$t0")
      a_asf+=" $(ate "$base-asf/keyframes.txt" "$base.gt.txt")"
      f_asf+=" $(awk -v n="$scans" -v t="$t" 'BEGIN{printf "%.1f", n / t}')"
      if ((ICP == 0)); then
        a_icp+=" -" f_icp+=" -"
        continue
      fi
      # icp-slam wants one record per frame (odometry as the action): normalize first.
      "$ASF" rawlog-normalize "$base.rawlog.gz" "$base.icp.rawlog" > /dev/null
      icp_ini "$base.icp.rawlog" "$base-icp" > "$base-icp.ini"
      t0=$(now_ms)
      icp-slam "$base-icp.ini" < /dev/null > "$base-icp.log" 2>&1
      t=$(seconds "$t0")
      a_icp+=" $(ate "$base-icp/log_estimated_path.txt" "$base.gt.txt" --frame-times "$base.icp.rawlog")"
      f_icp+=" $(awk -v n="$scans" -v t="$t" 'BEGIN{printf "%.1f", n / t}')"
      rm -f "$base.icp.rawlog"
    done
    printf "| %s | %s | %s | %s | %s | %s | %s |\n" "$name" "$scans" \
      "$(ates $a_odo)" "$(ates $a_asf)" \
      "$(ates $a_icp)" "$(echo $f_asf | median)" \
      "$(echo $f_icp | median)"
  done
  echo "(ATE per seed: $SEEDS; fps: median over the seeds. asf: $CONFIG ${ASF_SETS[*]-}. Outputs in $WORK)"
}

compare_simulated() {
  [[ -d "$LOGS" ]] || {
    echo "compare-icp-slam: MRPT sample data missing (apt-get install mrpt-common mrpt-apps)" >&2; exit 2; }
  printf "| log | scans | asf ATE RMSE [m] | asf wall [s] | icp-slam ATE RMSE [m] | icp-slam wall [s] |\n"
  printf "|---|---|---|---|---|---|\n"
  for name in simul range_030_bearing_015; do
    log=$LOGS/$name.rawlog gt=$LOGS/$name.rawlog.GT.txt cfg=configs/slam_simul.ini
    [[ $name == simul ]] || cfg=configs/slam_simul_noisy.ini
    # icp-slam asserts on odometry without timestamps (these logs have none): normalize first.
    scans=$("$ASF" rawlog-normalize "$log" "$WORK/$name.rawlog" | sed -n 's/.*(\([0-9]*\) scans).*/\1/p')
    icp_ini "$WORK/$name.rawlog" "$WORK/icp-slam-$name" > "$WORK/icp-slam-$name.ini"
    t0=$(now_ms)
    icp-slam "$WORK/icp-slam-$name.ini" < /dev/null > "$WORK/icp-slam-$name.log" 2>&1
    t_icp=$(seconds "$t0")
    # log_estimated_path.txt: frame index, x, y, phi (one line per frame of the log).
    a_icp=$(ate "$WORK/icp-slam-$name/log_estimated_path.txt" "$gt" --frame-times "$WORK/$name.rawlog")
    t0=$(now_ms)
    "$ASF" run "$cfg" -o "$WORK/asf-$name" --set pipeline.progress_interval=0 \
      > "$WORK/asf-$name.log" 2>&1
    t_asf=$(seconds "$t0")
    a_asf=$(ate "$WORK/asf-$name/keyframes.txt" "$gt")
    printf "| %s | %s | %.4f | %.2f | %.4f | %.2f |\n" "$name" "$scans" "$a_asf" "$t_asf" "$a_icp" "$t_icp"
  done
  echo "(asf: final keyframe poses; icp-slam: every frame's pose. Outputs in $WORK)"
}

case $SET in
  carmen) compare_carmen ;;
  simulated) compare_simulated ;;
  *) echo "compare-icp-slam: --set carmen|simulated" >&2; exit 2 ;;
esac
