#!/usr/bin/env bash
# Regenerate every result in results/ from the code as it is: each experiment in turn (one
# program per figure, table or study, each writing its CSV, plots and README.md), release build.
#
#   experiments/regenerate.sh            every experiment, in order (about 2–3 hours on 2 cores)
#   experiments/regenerate.sh NAME...    only these (experiment names, e.g. fig11_rocking_vs_regular)
#   experiments/regenerate.sh --quick    smoke test: build every experiment and run the fast ones
#   experiments/regenerate.sh --list     the experiments, in order
#
# A failed experiment is reported and the others still run; the script exits non-zero if any
# failed. Timings go to results/regenerate.log. results/report_html/ is CI's screenshot
# (.ci/report_html.sh), results/one_physics/ a hand-written comparison: neither is regenerated here.
# drops_vs_mujoco and drops_solver_substeps need MuJoCo's Python bindings (`pip install mujoco`;
# ROCKING_PYTHON names the interpreter, default python3): without them each says so and fails, and
# the others still run. shake_table_pgv and shake_table_sp1 need the folder of the SP1 shake-table
# tests, which is not in the repository: ROCKING_SP1 names it; without it each says so and writes
# nothing.
set -uo pipefail
cd "$(dirname "$0")/.."

# In dependency-free order: static first, then dynamics (the slow ones last).
ALL=(
  table1_planar_flocks fig2_planar_r_phi fig4_ellipse_grid fig5_rocking_planar
  static_scaling fig10_separation_of_scales fuzz_mutations table2_fit_nu hand_table2 fig12_hand_vs_computer
  housner_block corner_impact collider_step_cost drops_quasistatic_limit presets_flocks thick_coin cuboid_dice
  drops_settling drops_dt drops_certificate_speed certificate_margin drops_impacts drops_offfacet
  certificate_decisions drops_vs_mujoco drops_solver_substeps printed_shapes shake_table_pgv
  fig11_rocking_vs_regular fragility_shaking fragility_surface ensemble_fragility rocking_confusion_table
  open_scan_truth shake_table_sp1
)
# Seconds, not minutes: the static experiments (the smoke test of --quick).
QUICK=(table1_planar_flocks fig2_planar_r_phi fig4_ellipse_grid fig5_rocking_planar)

case "${1:-}" in
  --list) printf '%s\n' "${ALL[@]}"; exit 0 ;;
  --quick)
    cargo build --release --package experiments || exit 1
    run=("${QUICK[@]}") ;;
  "") run=("${ALL[@]}") ;;
  *) run=("$@") ;;
esac

log=results/regenerate.log
failed=()
for e in "${run[@]}"; do
  start=$SECONDS
  echo "== $e"
  args=()
  case "$e" in shake_table_pgv | shake_table_sp1) [ -n "${ROCKING_SP1:-}" ] && args=("$ROCKING_SP1") ;; esac
  # shake_table_sp1 also measures how its drawn ensembles move with the draw of the bases alone:
  # every 4th test, six seeds (results/shake_table_sp1/seed_spread/).
  [ "$e" = shake_table_sp1 ] && [ -n "${ROCKING_SP1:-}" ] &&
    ! cargo run --release --quiet --package experiments --bin "$e" -- "${args[@]}" --every 4 --bases drawn \
      --spread-seeds 2,3,4,5,6 --out results/shake_table_sp1/seed_spread && failed+=("$e seed_spread")
  if cargo run --release --quiet --package experiments --bin "$e" -- "${args[@]}"; then
    echo "$(date -u +%F) $e: $((SECONDS - start)) s" | tee -a "$log"
  else
    echo "$(date -u +%F) $e: FAILED after $((SECONDS - start)) s" | tee -a "$log"
    failed+=("$e")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "failed: ${failed[*]}"
  exit 1
fi
