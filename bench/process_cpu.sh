# CPU time and wake-ups of a process over a bench run, for the benchmark
# scripts. Source this file. Take process_sample before and after the run
# (with the run's wall-clock start and end), then print process_cpu_figures.

# "utime+stime ticks, context switches of all its threads" of a process.
process_sample() {  # pid
  local ticks switches
  ticks=$(awk '{print $14 + $15}' "/proc/$1/stat")
  switches=$(cat /proc/"$1"/task/*/status 2>/dev/null | awk '/^(non)?voluntary_ctxt_switches/ {n += $2} END {print n + 0}')
  echo "$ticks $switches"
}

# CPU share of one core and context switches per second between two samples.
process_cpu_figures() {  # start-sample end-sample start-seconds end-seconds
  awk -v a="$1" -v b="$2" -v s="$3" -v e="$4" -v hz="$(getconf CLK_TCK)" 'BEGIN {
    split(a, x, " "); split(b, y, " ")
    printf "%.1f%% of one core, %.0f context switches/s", (y[1] - x[1]) / hz / (e - s) * 100, (y[2] - x[2]) / (e - s)
  }'
}
