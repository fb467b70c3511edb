# Turns Google Benchmark JSON output (--benchmark_out=FILE --benchmark_out_format=json, run with
# --benchmark_repetitions=N --benchmark_report_aggregates_only=true) into one markdown table: per
# benchmark the median and the min over the repetitions (the `min` statistic that the bench
# programs register; "-" where one has none), the time per item (median) and the clock the time
# is on.
#   awk -f scripts/bench_to_markdown.awk build/bench/results/bench_*.json > table.md
# Time: CPU time for ordinary benchmarks (robust on a shared machine), the manual (GL timer) time
# for those registered with UseManualTime (their names end in /manual_time).
# Plain POSIX awk (mawk or gawk), no jq: it relies on the layout Google Benchmark writes (one
# "key": value per line, each benchmark an object closed by a line holding only "}" or "},").
# Without repetitions (plain runs) each benchmark's single result is shown as its median.

function value(line,    v) {
  v = line
  sub(/^[^:]*:[ \t]*/, "", v)
  sub(/,[ \t]*$/, "", v)
  if (v ~ /^".*"$/) v = substr(v, 2, length(v) - 2)
  return v
}

function fmt_time(v, unit,    ns) {
  if (v == "") return "-"
  ns = v * (unit == "ns" ? 1 : unit == "us" ? 1e3 : unit == "ms" ? 1e6 : 1e9)
  return fmt_ns(ns)
}

function fmt_ns(ns) {
  if (ns < 1e3) return sprintf("%.3g ns", ns)
  if (ns < 1e6) return sprintf("%.3g µs", ns / 1e3)
  if (ns < 1e9) return sprintf("%.3g ms", ns / 1e6)
  return sprintf("%.3g s", ns / 1e9)
}

function finish_record(    key, manual, t) {
  if (!have) return
  have = 0
  if (run_name == "") run_name = name
  key = program SUBSEP run_name
  if (!(key in seen)) { seen[key] = 1; order[++count] = key }
  if (error == "true") { err[key] = error_message; return }
  manual = (run_name ~ /manual_time$/)
  t = manual ? real_time : cpu_time
  if (agg == "median" || agg == "") {
    med[key] = t; unit[key] = time_unit; ips[key] = items; clk[key] = manual ? "GL timer" : "CPU"
  }
  if (agg == "min") mn[key] = t
}

FNR == 1 {
  finish_record()
  program = FILENAME
  sub(/^.*\//, "", program)
  sub(/\.json$/, "", program)
  in_list = 0
}

/^[ \t]*"benchmarks":/ { in_list = 1; next }

in_list && /^[ \t]*"name":/ {
  finish_record()
  have = 1; name = value($0); run_name = ""; agg = ""; real_time = ""; cpu_time = ""
  time_unit = "ns"; items = ""; error = ""; error_message = ""
  next
}
in_list && have && /^[ \t]*"run_name":/ { run_name = value($0); next }
in_list && have && /^[ \t]*"aggregate_name":/ { agg = value($0); next }
in_list && have && /^[ \t]*"real_time":/ { real_time = value($0); next }
in_list && have && /^[ \t]*"cpu_time":/ { cpu_time = value($0); next }
in_list && have && /^[ \t]*"time_unit":/ { time_unit = value($0); next }
in_list && have && /^[ \t]*"items_per_second":/ { items = value($0); next }
in_list && have && /^[ \t]*"error_occurred":/ { error = value($0); next }
in_list && have && /^[ \t]*"error_message":/ { error_message = value($0); next }
in_list && have && /^[ \t]*},?[ \t]*$/ { finish_record(); next }

END {
  finish_record()
  print "| program | benchmark | median | min | per item (median) | clock |"
  print "|---|---|---|---|---|---|"
  for (i = 1; i <= count; i++) {
    key = order[i]
    split(key, parts, SUBSEP)
    if (key in err) { printf "| %s | `%s` | error: %s | | | |\n", parts[1], parts[2], err[key]; continue }
    per = (ips[key] != "" && ips[key] + 0 > 0) ? fmt_ns(1e9 / ips[key]) : "-"
    printf "| %s | `%s` | %s | %s | %s | %s |\n", parts[1], parts[2], fmt_time(med[key], unit[key]),
           fmt_time(mn[key], unit[key]), per, clk[key]
  }
}
