#!/bin/sh
# gimbalsim simulate's CSV and summary commit together: when the summary's
# directory vanishes during the run, the run exits 4 and leaves no file under
# either requested name. Usage: cli_outputs_commit_together.sh GIMBALSIM SCENE WORKDIR
bin=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work/s" || exit 1
"$bin" simulate "$scene" --set sim.duration=600 --out "$work/run.csv" --summary "$work/s/summary.json" &
pid=$!
# Bounded wait (at most 3000 polls) for the summary's temporary, made before the first step.
i=0
until ls -A "$work/s" | grep -q '\.tmp$'; do
  i=$((i + 1)); [ $i -gt 3000 ] && { kill -INT $pid; echo "no temporary appeared"; exit 1; }
  sleep 0.01
done
rm -rf "$work/s"
kill -INT $pid  # end the long run early; it still commits (and here fails to)
wait $pid
rc=$?
echo "left: [$(ls -A "$work" | tr '\n' ' ')] exit=$rc;"
