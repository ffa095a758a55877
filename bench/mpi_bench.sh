#!/usr/bin/env bash
# MPI benchmark: evaluations per second of `sodaevo evolve` with 1 and 2 MPI ranks
# (one evaluation thread each), checked to give identical run folders, plus the
# measured inputs of the scaling model (docs/cluster.md) and the
# model's expected efficiency at 10, 100 and 1000 ranks.
#
#   bench/mpi_bench.sh [REPEATS]     (default 7; median of the repeats)
#
# Writes results/bench/mpi.csv (every run) and results/bench/mpi.md (the table and
# the model). Run it with the machine otherwise idle. Needs an MPI build and mpirun.
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-7}
BIN=${SODAEVO_BIN:-build/sodaevo}
CONFIG=bench/mpi_bench.json
OUT=results/bench
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$OUT"
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)
"$BIN" --version | grep -q "MPI: yes" || { echo "mpi_bench: $BIN was built without MPI" >&2; exit 2; }
command -v mpirun >/dev/null || { echo "mpi_bench: mpirun not found (apt-get install openmpi-bin)" >&2; exit 2; }
MPIRUN=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && MPIRUN+=(--allow-run-as-root)

echo "ranks,repeat,evaluations,wall_seconds,evaluation_seconds,evals_per_second,evals_per_second_evaluating,bytes_sent_per_creature,bytes_returned_per_creature,cpu_seconds,cores_obtained" >"$WORK/runs.csv"
TIMEFORMAT='%R %U %S'   # bash's time: wall, then user and system CPU of mpirun and every rank
for rep in $(seq 1 "$REPEATS"); do
  for ranks in 1 2; do
    dir="$WORK/np$ranks-$rep"
    times=$( { time "${MPIRUN[@]}" -np "$ranks" "$BIN" evolve "$CONFIG" --out "$dir" --threads 1 >"$WORK/out" 2>"$WORK/err"; } 2>&1 )
    read -r t_wall t_user t_sys <<<"$times"
    # timing.csv: generation,evaluations,wall_seconds (cumulative),evaluations_per_second (of that generation's evaluation)
    read -r evals wall eval_s < <(awk -F, 'NR>1 { if ($4 > 0) t += ($2 - prev) / $4; prev = $2; e = $2; w = $3 } END { printf "%d %.6f %.6f\n", e, w, t }' "$dir/timing.csv")
    sent=$(sed -n 's/.*; \([0-9.]*\) bytes per creature sent.*/\1/p' "$WORK/err")
    back=$(sed -n 's/.*sent, \([0-9.]*\) bytes per creature returned.*/\1/p' "$WORK/err")
    awk -v r="$ranks" -v rep="$rep" -v e="$evals" -v w="$wall" -v t="$eval_s" -v s="${sent:-0}" -v b="${back:-0}" \
      -v cpu="$(awk -v u="$t_user" -v s="$t_sys" 'BEGIN { print u + s }')" -v tw="$t_wall" \
      'BEGIN { printf "%d,%d,%d,%.6f,%.6f,%.1f,%.1f,%s,%s,%.3f,%.2f\n", r, rep, e, w, t, e / w, e / t, s, b, cpu, cpu / tw }' >>"$WORK/runs.csv"
    echo "mpi_bench: repeat $rep, $ranks rank(s): $(tail -1 "$WORK/runs.csv")" >&2
  done
  for f in generations.csv best; do
    diff -r "$WORK/np1-$rep/$f" "$WORK/np2-$rep/$f" >/dev/null || { echo "mpi_bench: 1 and 2 ranks differ in $f" >&2; exit 1; }
  done
done
cp "$WORK/runs.csv" "$OUT/mpi.csv"

# The model's inputs in CPU time, which other work on the machine hardly changes
# (wall times do): the benchmark run in one process, and the same run with 1-frame
# trials and 10 times the generations (rank 0's serial work alone: selection,
# variation, XML, checkpoints, plus the trivial trials). Its wall time minus CPU
# time is mostly waiting for the disk (every file of the run folder is fsync'ed),
# though on a loaded machine also waiting for a core.
sed 's/"frames": *[0-9]*/"frames": 1/; s/"settle_frames": *[0-9]*/"settle_frames": 0/; s/"generations": *\([0-9]*\)/"generations": \10/' \
  "$CONFIG" >bench/.mpi_bench_serial.json
serial=$( { time "$BIN" evolve bench/.mpi_bench_serial.json --out "$WORK/serial" --threads 1 --quiet >/dev/null; } 2>&1 )
rm -f bench/.mpi_bench_serial.json
full=$( { time "$BIN" evolve "$CONFIG" --out "$WORK/full" --threads 1 --quiet >/dev/null; } 2>&1 )
read -r s_wall s_user s_sys <<<"$serial"
read -r f_wall f_user f_sys <<<"$full"
s_gens=$(($(wc -l <"$WORK/serial/generations.csv") - 1))
LOAD_AFTER=$(cut -d' ' -f1-3 /proc/loadavg)

# Medians over the repeats, then the scaling model.
awk -F, -v f_cpu="$(awk -v u="$f_user" -v s="$f_sys" 'BEGIN { print u + s }')" -v s_wall="$s_wall" -v s_cpu="$(awk -v u="$s_user" -v s="$s_sys" 'BEGIN { print u + s }')" -v s_gens="$s_gens" -v load="$LOAD_BEFORE before, $LOAD_AFTER after" -v gens="$(sed -n 's/.*"generations": *\([0-9]*\).*/\1/p' "$CONFIG")" \
  -v shape="$(sed -n 's/.*"size": *\([0-9]*\).*/\1/p' "$CONFIG") creatures, $(sed -n 's/.*"frames": *\([0-9]*\).*/\1/p' "$CONFIG") frames" -v cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')" -v cores="$(nproc)" '
  function median(a, n,   i, j, t) { for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                     return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
  NR > 1 { if ($1 == 1) one[$2] = $6; else if ($2 in one) { np++; ratio[np] = $6 / one[$2] }
           k = $1; n[k]++; rate[k, n[k]] = $6; per_cpu[k, n[k]] = $3 / $10; got[k, n[k]] = $11; erate[k, n[k]] = $7; wall[k, n[k]] = $4; evs[k, n[k]] = $5; evals = $3
           if ($1 == 2) { sent = $8; back = $9 } }
  END {
    for (k = 1; k <= 2; k++) {
      for (i = 1; i <= n[k]; i++) { a[i] = rate[k, i]; b[i] = erate[k, i]; c[i] = wall[k, i]; d[i] = evs[k, i] }
      R[k] = median(a, n[k]); E[k] = median(b, n[k]); W[k] = median(c, n[k]); T[k] = median(d, n[k])
      lo[k] = a[1]; hi[k] = a[n[k]]                     # median() sorted a
      for (i = 1; i <= n[k]; i++) { a[i] = per_cpu[k, i]; b[i] = got[k, i] }
      PC[k] = median(a, n[k]); CO[k] = median(b, n[k])
    }
    P0 = evals / gens                   # creatures evaluated per generation (about)
    tcpu = s_cpu / s_gens / P0          # rank 0 serial CPU per creature (an upper bound: includes the 1-frame trials)
    te = (f_cpu - tcpu * evals) / evals # CPU per evaluation, one thread
    tio = (s_wall - s_cpu) / s_gens     # disk (and, on a loaded machine, core) waits per generation
    m = sent + back                     # bytes per creature over the wire
    printf "# MPI benchmark\n\n"
    printf "`bench/mpi_bench.sh %d` on %s (%d cores; load average %s), `bench/mpi_bench.json`\n", n[1], cpu, cores, load
    printf "(%d evaluations: %d generations of %s), one evaluation thread per rank,\n", evals, gens, shape
    printf "median of %d repeats; the run folders of 1 and 2 ranks were checked identical. Every run: `mpi.csv`.\n\n", n[1]
    printf "| ranks | evaluations/s (whole run) | range over the repeats | evaluations/s (while evaluating) | speed-up (whole run) | speed-up (evaluating) |\n|---|---|---|---|---|---|\n"
    for (k = 1; k <= 2; k++) printf "| %d | %.0f | %.0f-%.0f | %.0f | %.2fx | %.2fx |\n", k, R[k], lo[k], hi[k], E[k], R[k] / R[1], E[k] / E[1]
    printf "\nSpeed-up of 2 ranks over 1, median of the %d paired repeats (each 1-rank run is followed at once\n", np
    printf "by its 2-rank run, so both see about the same load from other work): **%.2fx** (whole run).\n", median(ratio, np)
    printf "\nWhat the machine gave (medians; CPU time of mpirun and every rank, from bash'\''s time):\n\n"
    printf "| ranks | cores obtained (CPU s / wall s) | evaluations per CPU second |\n|---|---|---|\n"
    for (k = 1; k <= 2; k++) printf "| %d | %.2f | %.0f |\n", k, CO[k], PC[k]
    printf "\nEvaluations per CPU second are what the MPI evaluator costs: equal for 1 and 2 ranks means\n"
    printf "farming creatures out adds no work; the speed-up then follows the cores the machine gives.\n"
    printf "\nMeasured inputs of the scaling model (CPU times, from single-process runs):\n\n"
    printf "- evaluation time per creature t_e = %.2f ms of CPU (one thread; run of %s)\n", te * 1000, shape
    printf "- rank 0 serial work per generation: t_io = %.1f ms of waiting (for the disk: each file is fsync'\''ed; here also for a core) + t_cpu = %.0f us of CPU per creature (selection, variation, XML, checkpoint)\n", tio * 1000, tcpu * 1e6
    printf "- message size per creature m = %.0f bytes out (the genome) + %.0f bytes back (the evaluation)\n\n", sent, back
    printf "Model, per generation, population P, N ranks of one thread, rank 0 serving every chunk:\n\n"
    printf "    T_N = t_io + P*t_cpu + max(ceil(P/N)*t_e, c*N*o + P*m/B) + t_e,   E(N) = T_1 / (N*T_N)\n\n"
    printf "with o = 20 us per message exchange at rank 0 (Ethernet-class; a few us on InfiniBand), B = 1 GB/s,\n"
    printf "c = 1 + log2(max(P/N, 1)) guided chunks per rank, and t_e once more for the last chunk.\n\n"
    printf "| P | E(10) | E(100) | E(1000) |\n|---|---|---|---|\n"
    split("1000 10000 100000", Ps, " ")
    for (pi = 1; pi <= 3; pi++) {
      P = Ps[pi]; T1 = tio + P * tcpu + P * te + te
      printf "| %d |", P
      split("10 100 1000", Ns, " ")
      for (ni = 1; ni <= 3; ni++) {
        N = Ns[ni]; per = P / N; chunks = 1 + (per > 1 ? log(per) / log(2) : 0)
        comp = (P % N ? int(P / N) + 1 : P / N) * te; comm = chunks * N * 20e-6 + P * m / 1e9
        TN = tio + P * tcpu + (comp > comm ? comp : comm) + te
        printf " %.0f%% |", 100 * T1 / (N * TN)
      }
      printf "\n"
    }
  }' "$OUT/mpi.csv" >"$OUT/mpi.md"
cat "$OUT/mpi.md"
