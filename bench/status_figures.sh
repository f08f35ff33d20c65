# Figures from two `ecpairctl status` texts of the same ecpaird (at the start
# and at the end of a run), for the benchmark scripts. Source this file; set
# start_status and end_status first.

# The number after LABEL in a status text.
status_number() { grep -oE "$2 [0-9]+" <<<"$1" | head -1 | grep -oE '[0-9]+$'; }
status_late() { grep -oE '\(([0-9]+) late' <<<"$1" | grep -oE '[0-9]+'; }
# How much LABEL grew from start_status to end_status.
status_delta() { echo $(( $(status_number "$end_status" "$1") - $(status_number "$start_status" "$1") )); }

# The cycle figures of the run: cycles, late, frames sent and lost, late
# copies, incomplete cycles, WKC errors, and the whole run's wake-up latency.
print_cycle_figures() {
  echo "  cycles:           $(status_delta cycles)"
  echo "  late cycles:      $(( $(status_late "$end_status") - $(status_late "$start_status") ))   (woke more than a quarter period after the deadline)"
  grep -oE 'cycles [0-9]+ \([^)]*\)' <<<"$end_status" | sed 's/^/  whole run:        /'
  echo "  frames sent:      $(status_delta 'frames sent')"
  echo "  frames lost:      $(status_delta 'lost')   (not complete when the next cycle started)"
  echo "  late copies:      $(status_delta 'late copies')   (on MAIN $(status_delta 'on MAIN'), on RED $(status_delta 'on RED'))"
  echo "  incomplete cycles: $(status_delta 'incomplete cycles')"
  echo "  WKC errors:       $(status_delta 'WKC errors')"
}
