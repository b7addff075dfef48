# The loops of an avm-odometry run beside their own uncertainty: how many times
# the worst-axis sigma its inliers alone give (the loop status of --stats,
# "(inliers S m)") a loop is off the ground truth (measured_error_m of --loops),
# and the least-squares fit of the per-axis squared error to a floor plus a
# multiple of that sigma squared (loop_sigma; a multiple that weighed loops by
# their inliers made the runs worse, so the loop check does not use one).
# Usage: awk -f scripts/loop-error-fit.awk STATS.csv LOOPS.csv
FNR == NR { if (match($0, /inliers [0-9.]+ m\)/)) { split($0, c, ","); s[c[1]] = substr($0, RSTART + 8, RLENGTH - 11) + 0 } next }
FNR > 1 { split($0, c, ","); if (!(c[1] in s)) next; x = s[c[1]]^2; y = c[21]^2 / 3; n++
  sx += x; sy += y; sxx += x * x; sxy += x * y; r[n] = c[21] / s[c[1]] }
END { b = (n * sxy - sx * sy) / (n * sxx - sx * sx); a = (sy - b * sx) / n
  for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (r[j] < r[i]) { t = r[i]; r[i] = r[j]; r[j] = t }
  printf "%d loops, error / inlier sigma: median %.1f; fit error^2/3 = a^2 + k^2 sigma^2: a %.4f m, k %.2f\n", n, r[int((n + 1) / 2)], sqrt(a > 0 ? a : 0), sqrt(b > 0 ? b : 0) }
