#!/usr/bin/env bash
# SLAM accuracy side by side: asf (configs/slam_simul.ini and slam_simul_noisy.ini, icp_graph +
# sparse_lm) and MRPT's icp-slam (its Levenberg-Marquardt demo config) on MRPT's two simulated
# graphslam-engine logs with ground truth. Prints the ATE (RMSE after SE(2) alignment, `asf ate`) and wall times.
# Needs the built host (scripts/build.sh) and icp-slam (Debian package mrpt-apps).
#   usage: scripts/compare-icp-slam.sh [WORK_DIR]   (default: results/compare-icp-slam)
set -euo pipefail
cd "$(dirname "$0")/.."
ASF=${ASF:-build/bin/asf}
WORK=${1:-results/compare-icp-slam}
LOGS=/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map
ICP_INI=/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_LM.ini
[[ -x "$ASF" ]] || { echo "compare-icp-slam: $ASF not built (run scripts/build.sh)" >&2; exit 2; }
command -v icp-slam >/dev/null || {
  echo "compare-icp-slam: icp-slam not found (apt-get install mrpt-apps)" >&2; exit 2; }
[[ -f "$ICP_INI" && -d "$LOGS" ]] || {
  echo "compare-icp-slam: MRPT sample data missing (apt-get install mrpt-common mrpt-apps)" >&2; exit 2; }
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)

now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
seconds() { local ms=$(( $(now_ms) - $1 )); printf "%d.%03d" $((ms / 1000)) $((ms % 1000)); }
ate() { "$ASF" ate "$@" --json | sed -n 's/.*"ate_rmse_m": \([0-9.e-]*\).*/\1/p'; }

printf "| log | scans | asf ATE RMSE [m] | asf wall [s] | icp-slam ATE RMSE [m] | icp-slam wall [s] |\n"
printf "|---|---|---|---|---|---|\n"
for name in simul range_030_bearing_015; do
  log=$LOGS/$name.rawlog gt=$LOGS/$name.rawlog.GT.txt cfg=configs/slam_simul.ini
  [[ $name == simul ]] || cfg=configs/slam_simul_noisy.ini
  # icp-slam asserts on odometry without timestamps (these logs have none): normalize first.
  scans=$("$ASF" rawlog-normalize "$log" "$WORK/$name.rawlog" | sed -n 's/.*(\([0-9]*\) scans).*/\1/p')
  sed -e "s|^rawlog_file\s*=.*|rawlog_file=$WORK/$name.rawlog|" \
      -e "s|^logOutput_dir\s*=.*|logOutput_dir=$WORK/icp-slam-$name|" \
      -e "s|^SHOW_PROGRESS_3D_REAL_TIME\s*=.*|SHOW_PROGRESS_3D_REAL_TIME=false|" \
      -e "s|^SAVE_3D_SCENE\s*=.*|SAVE_3D_SCENE=0|" "$ICP_INI" > "$WORK/icp-slam-$name.ini"
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
