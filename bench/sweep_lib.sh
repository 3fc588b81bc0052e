# Helpers shared by the bench/case_study_*.sh scripts (source it).
# done_sweep DIR VALUES: true if DIR/sweep.csv exists and holds exactly VALUES (comma-separated),
# so a re-run can reuse it.
done_sweep() { [ -f "$1/sweep.csv" ] && [ "$(cut -d, -f1 "$1/sweep.csv" | tail -n +2 | paste -sd,)" = "$2" ]; }
