#!/usr/bin/env bash
# The papers' figures that ROME reproduces, regenerated from the example programs (./rome figures calls this).
#
# usage: rome_figures.sh BIN_DIR OUT_DIR [--quick]
#   BIN_DIR  the folder of stepping_stones, walking, hopping and rome_sweep (build/bin)
#   OUT_DIR  written afresh: OUT_DIR/{stepping-stones,walking,hopping}/figN_<what>.png, each PNG with a caption strip
#            naming the paper's figure and the command that drew it; OUT_DIR/<paper>/captions.txt lists the captions;
#            the runs' outputs, logs and summaries in OUT_DIR/runs/; the headline numbers in OUT_DIR/numbers.md
#   --quick  the same figures from short runs (few steps, a 2-point sweep): what tests/examples/figures_test.py checks
# Needs gnuplot (the examples' plotter; it also draws the caption strips), python3 and, for the sweeps, mpirun.
# Exit codes: 0 every figure written, 3 a program failed or a figure is missing, 1 bad arguments.
set -uo pipefail

usage() { echo "usage: rome_figures.sh BIN_DIR OUT_DIR [--quick]" >&2; exit 1; }
[ $# -ge 2 ] && [ $# -le 3 ] || usage
BIN="$1" OUT="$2" QUICK=0
if [ $# -eq 3 ]; then [ "$3" = --quick ] && QUICK=1 || { echo "rome_figures.sh: unknown option '$3' (expected --quick)" >&2; exit 1; }; fi
for p in stepping_stones walking hopping rome_sweep; do
  [ -x "$BIN/$p" ] || { echo "rome_figures.sh: BIN_DIR '$BIN' has no program '$p' (build it: ./rome build)" >&2; exit 1; }
done
for p in gnuplot python3 mpirun; do
  command -v "$p" > /dev/null || { echo "rome_figures.sh: '$p' is not installed (./rome setup installs it)" >&2; exit 1; }
done
case "$OUT" in ''|/) echo "rome_figures.sh: refusing OUT_DIR '$OUT'" >&2; exit 1 ;; esac

RUNS="$OUT/runs"
STATUS=0
WRITTEN=()
rm -rf "$OUT" && mkdir -p "$RUNS" || { echo "rome_figures.sh: cannot create '$RUNS'" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
CMD=()  # the last command fig_run ran, for the captions

run() {  # run NAME COMMAND...: runs a program, its output in $RUNS/NAME.txt; returns its exit code
  local name="$1"; shift
  CMD=("$@")
  echo "[figures] $name: $*"
  local code=0
  "$@" > "$RUNS/$name.txt" 2>&1 || code=$?
  if [ "$code" -ne 0 ]; then
    echo "[figures] FAILED: $name (exit code $code; output in $RUNS/$name.txt)" >&2
    STATUS=3
  fi
  return "$code"
}

# caption PNG TEXT: redraws PNG with a strip under it: TEXT (the paper's figure) and the command of the last run, each
# folded to the image's width.
caption() {
  local png="$1" text="$2" size w h command="${CMD[*]}"
  size=$(python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(24); print(*struct.unpack(">II", d[16:24]))' "$png") || return 1
  read -r w h <<< "$size"
  command="command: ${command//$BIN\//}"  # the program's name, not the build folder
  local -a lines small
  mapfile -t lines < <(fold -s -w $((w / 7)) <<< "$text")
  mapfile -t small < <(fold -s -w $((w / 6)) <<< "$command")
  local strip=$((${#lines[@]} * 16 + ${#small[@]} * 13 + 8)) y q="'" k labels=""
  y=$((strip - 13))
  for k in "${lines[@]}"; do
    labels+="set label '${k//$q/$q$q}' at screen 0.005, screen $y.0/$((h + strip)) left"$'\n'; y=$((y - 16))
  done
  y=$((y + 2))
  for k in "${small[@]}"; do
    labels+="set label '${k//$q/$q$q}' at screen 0.005, screen $y.0/$((h + strip)) left font ',8'"$'\n'; y=$((y - 13))
  done
  gnuplot 2> "$png.caption.err" > "$png.tmp" <<EOF || { rm -f "$png.tmp"; return 1; }
set terminal pngcairo size $w,$((h + strip)) noenhanced font ",10"
set lmargin at screen 0; set rmargin at screen 1; set tmargin at screen 1; set bmargin at screen $strip.0/$((h + strip))
unset border; unset tics; unset key
set xrange [-0.5:$w-0.5]; set yrange [-0.5:$h-0.5]
$labels
plot '$png' binary filetype=png with rgbimage
EOF
  [ -s "$png.tmp" ] && mv "$png.tmp" "$png" && rm -f "$png.caption.err"
}

# figure SRC_DIR PAPER SRC_NAME DEST_NAME CAPTION: copies a PNG (captioned) or CSV under its figure name.
figure() {
  local from="$1/$3" dir="$OUT/$2" to="$OUT/$2/$4" text="$5"
  mkdir -p "$dir"
  if [ ! -s "$from" ]; then
    echo "[figures] FAILED: $from was not written" >&2; STATUS=3; return
  fi
  cp "$from" "$to"
  if [[ "$to" == *.png ]] && ! caption "$to" "$text"; then
    echo "[figures] FAILED: the caption of $to (gnuplot: $(head -c 300 "$to.caption.err" 2> /dev/null))" >&2; STATUS=3
  fi
  [ -z "$text" ] || printf '%s\t%s\tcommand: %s\n' "$4" "$text" "${CMD[*]//$BIN\//}" >> "$dir/captions.txt"
  WRITTEN+=("$to")
}

SS="Stepping stones (Xiong & Ames)"
WK="Walking (Xiong & Ames, aSLIP + H-LIP)"
HP="Hopping (Xiong & Ames, Cassie)"
if [ $QUICK -eq 1 ]; then STEPS=6 DOWN_STEPS=6 WALK_STEPS=2 SWEEP_STEPS=4; else STEPS=30 DOWN_STEPS=10 WALK_STEPS=10 SWEEP_STEPS=15; fi

# --- Stepping stones: Fig. 4 (flat l = 0.7 m, stairs up (0.5, 0.2) m, stairs down (0.4, -0.1) m) and Fig. 5 (the stairs
# down, logged every 1 ms so that the pre-impact sample is at most 1 ms before the impact) for both robots; Fig. 7 on
# random stones (seed 1, E* = 0.5, epsilon = 0.6) for both robots. All at the paper's E* = 0.5 (AMBER's default is 0.4).
for robot in amber cassie_planar; do
  ss=("$BIN/stepping_stones" --robot "robots/$robot/$robot.rome.json" --log-period 0.001 --energy 0.5)
  name="AMBER"; [ $robot = cassie_planar ] && name="planar Cassie"
  for terrain in "flat 0.7 0" "stairs-up 0.5 0.2" "stairs-down 0.4 -0.1"; do
    read -r kind l h <<< "$terrain"
    tag="ss_${kind}_$robot" n=$STEPS
    [ "$kind" = stairs-down ] && n=$DOWN_STEPS
    args=(--terrain "$kind" --step-length "$l" --steps "$n")
    [ "$kind" = flat ] || args+=(--step-height "$h")
    run "$tag" "${ss[@]}" "${args[@]}" --plots "$RUNS/$tag" --summary "$RUNS/$tag.json" || continue
    figure "$RUNS/$tag" stepping-stones gait_tiles.png "fig4_${kind}_${robot}_gait_tiles.png" \
      "$SS Fig. 4: $name walking on $kind, (l, h) = ($l, $h) m, converging to a periodic gait"
    if [ "$kind" = stairs-down ]; then
      figure "$RUNS/$tag" stepping-stones outputs.png "fig5_${robot}_outputs.png" \
        "$SS Fig. 5: $name's outputs on stairs down (0.4, -0.1) m, desired vs actual"
      figure "$RUNS/$tag" stepping-stones pre_impact_vz.png "fig5_${robot}_pre_impact_vz.png" \
        "$SS Fig. 5 (a, b): $name's pre-impact COM vertical velocity against u_des, per step"
      figure "$RUNS/$tag" stepping-stones pre_impact_vz.csv "fig5_${robot}_pre_impact_vz.csv" ""
    fi
  done
  tag="ss_random_$robot"
  run "$tag" "${ss[@]}" --terrain random --seed 1 --steps "$STEPS" --plots "$RUNS/$tag" --summary "$RUNS/$tag.json" || continue
  for plot in gait_tiles com_height phase_portrait; do
    figure "$RUNS/$tag" stepping-stones "$plot.png" "fig7_${robot}_$plot.png" \
      "$SS Fig. 7: $name on random stones (seed 1; E* = 0.5, epsilon = 0.6): ${plot//_/ }"
  done
done

# Fig. 6 (flat ground, epsilon = 0.6, AMBER): (a) speed over l at E* = 0.3, (b) speed over E* at l = 0.4 m, one run per
# point over MPI (2 ranks).
if [ $QUICK -eq 1 ]; then LGRID=0.3:0.6:2 EGRID=0.2:0.5:2; else LGRID=0.1:0.8:8 EGRID=0.1:0.7:7; fi
sweep=(mpirun -np 2 "$BIN/rome_sweep" stepping-stones)
# AMBER's stones are 0.1 m long by default (point feet): 5 cm stones let the sweep start at the paper's l = 0.1 m.
run ss_fig6a "${sweep[@]}" --grid step-length=$LGRID --set energy=0.3 --set terrain=flat --set steps=$SWEEP_STEPS \
  --set stone-length=0.05 \
  --out "$RUNS/ss_fig6a" &&
  figure "$RUNS/ss_fig6a" stepping-stones sweep_speed.png fig6a_speed_over_step_length.png \
    "$SS Fig. 6a: AMBER's mean forward speed over the step length l (flat, E* = 0.3, epsilon = 0.6)" &&
  figure "$RUNS/ss_fig6a" stepping-stones sweep.csv fig6a_sweep.csv ""
run ss_fig6b "${sweep[@]}" --grid energy=$EGRID --set step-length=0.4 --set terrain=flat --set steps=$SWEEP_STEPS \
  --out "$RUNS/ss_fig6b" &&
  figure "$RUNS/ss_fig6b" stepping-stones sweep_speed.png fig6b_speed_over_energy.png \
    "$SS Fig. 6b: AMBER's mean forward speed over the orbital energy E* (flat, l = 0.4 m, epsilon = 0.6)" &&
  figure "$RUNS/ss_fig6b" stepping-stones sweep.csv fig6b_sweep.csv ""

# --- Walking (the exoskeleton from standing, the default scenario; the NLP plans cached in runs/walking_plans).
if run walking "$BIN/walking" --steps "$WALK_STEPS" --cache "$RUNS/walking_plans" --plots "$RUNS/walking" \
  --summary "$RUNS/walking.json"; then
  w="$RUNS/walking"
  figure "$w" walking aslip_periodic.png fig2_s2_aslip_periodic.png \
    "$WK Fig. 2 S2: the periodic aSLIP over one step: COM height, per-leg vertical force, forward velocity"
  figure "$w" walking hlip_p2_portrait.png fig2_l2_hlip_p2_portrait.png \
    "$WK Fig. 2 L2: the H-LIP period-2 orbit in the lateral phase plane, with its sigma_2 lines"
  figure "$w" walking transition_start_sagittal.png fig3_s2_transition_start_sagittal.png \
    "$WK Fig. 3 S2: the footed aSLIP transition (start gait -> gait A), nodes in DSP blue, SSP red, ZMP bounds"
  figure "$w" walking transition_start_lateral.png fig3_l2_transition_start_lateral.png \
    "$WK Fig. 3 L2: the footed H-LIP transition (start gait -> gait A), nodes in DSP blue, SSP red, ZMP bounds"
  figure "$w" walking transition_sagittal.png fig3_s2_transition_sagittal.png \
    "$WK Fig. 3 S2: the footed aSLIP transition from standing, nodes in DSP blue, SSP red, ZMP bounds"
  figure "$w" walking transition_lateral.png fig3_l2_transition_lateral.png \
    "$WK Fig. 3 L2: the footed H-LIP transition from standing, nodes in DSP blue, SSP red, ZMP bounds"
  figure "$w" walking com.png fig5a_com.png "$WK Fig. 5a: COM position, desired vs actual, and the error"
  figure "$w" walking com_velocity.png fig5b_com_velocity.png "$WK Fig. 5b: COM velocity, desired vs actual, and the error"
  figure "$w" walking gait_tiles_sagittal.png fig5c_gait_tiles_sagittal.png "$WK Fig. 5c: gait tiles from standing, sagittal"
  figure "$w" walking gait_tiles_frontal.png fig5c_gait_tiles_frontal.png "$WK Fig. 5c: gait tiles from standing, frontal"
  figure "$w" walking normal_forces.png fig5d_normal_forces.png \
    "$WK Fig. 5d: each foot's plant normal force inside the relaxation band of Eq. (25)"
fi

# --- Hopping (Cassie, one hop, hybrid plant).
if run hopping "$BIN/hopping" --plots "$RUNS/hopping" --summary "$RUNS/hopping.json"; then
  h="$RUNS/hopping"
  figure "$h" hopping output_leg_length.png fig6ab_output_leg_length.png \
    "$HP Fig. 6a,b: leg-length output in Jump and Landing: actual, target, ROM plan"
  figure "$h" hopping output_com_x.png fig6ab_output_com_x.png "$HP Fig. 6a,b: COM x output in Jump and Landing"
  figure "$h" hopping output_pitch.png fig6ab_output_pitch.png "$HP Fig. 6a,b: pelvis pitch output in Jump and Landing"
  figure "$h" hopping energy.png fig6c_energy.png "$HP Fig. 6c: spring, kinetic and potential energy, robot vs spring-mass ROM"
  figure "$h" hopping spring_torque.png fig6d_spring_torque.png "$HP Fig. 6d: shin spring torque and the normal force it carries"
  figure "$h" hopping pitch_momentum.png fig6e_pitch_momentum.png "$HP Fig. 6e: centroidal pitch momentum during the hop"
  figure "$h" hopping grf.png fig6f_grf.png "$HP Fig. 6f: normal GRF of Cassie vs the spring-mass model, by domain"
  figure "$h" hopping hop_tiles.png fig7e_hop_tiles.png "$HP Fig. 7e: hop snapshots (simulation), sagittal projection"
fi

# The headline numbers beside the papers' (docs/figures.md quotes them).
if python3 "$(dirname "$0")/figures_numbers.py" "$OUT" > "$OUT/numbers.md"; then
  WRITTEN+=("$OUT/numbers.md")
else
  echo "[figures] FAILED: the headline numbers (figures_numbers.py)" >&2; STATUS=3
fi
echo "[figures] ${#WRITTEN[@]} files written:"
printf '  %s\n' "${WRITTEN[@]}"
[ "$STATUS" -eq 0 ] || echo "[figures] some programs or figures failed (see above)" >&2
exit "$STATUS"
