#!/bin/bash
# The probes of issue 58 (docs/files.md), each as one line: exit status, stderr lines, tracebacks, last line.
# Usage: bash benchmarks/probes/output_policy.sh   (PY=... and PYTHONPATH=OTHER/mentor_core/src to probe another checkout)
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
PY="${PY:-$ROOT/.venv/bin/python}"
W=$(mktemp -d); cd "$W"
P=$ROOT/planners/swarm-paper-dual-s1.json; U=$ROOT/bags/unseen/swarm
probe() { name=$1; shift; timeout 120 "$@" > out.txt 2> err.txt; rc=$?; lines=$(wc -l < err.txt); tb=$(grep -c Traceback err.txt); echo "$name: rc=$rc stderr_lines=$lines traceback=$tb :: $(tail -1 err.txt | cut -c1-150)"; }
"$PY" -c "
a='n_scenarios:\n  - &a [\"x\",\"x\",\"x\",\"x\",\"x\",\"x\",\"x\",\"x\",\"x\"]\n'
for x,y in zip('abcdefgh','bcdefghi'): a+=f'  - &{y} [' + ', '.join([f'*{x}']*9) + ']\n'
open('bomb.yaml','w').write(a)
open('deep.yaml','w').write('value: ' + '['*600 + ']'*600 + '\n')
open('dup.yaml','w').write('extends: swarm/quick\ngenerations: 3\ngenerations: 4\n')
open('u.yaml','w').write('extends: swarm/quick\nn_scenarios: 1_2\n')
open('r.yaml','w').write('extends: swarm/quick\nrobot: ugv\n')
"
probe bomb timeout 20 $PY -m mentor_core.cli.train --robot swarm --framework dual --config bomb.yaml --out r1
probe deep-config $PY -m mentor_core.cli.train --robot swarm --framework dual --config deep.yaml --out r2
probe n_scenarios $PY -m mentor_core.cli.train --robot swarm --framework dual --set n_scenarios=20000 --out r3
probe eval-n $PY -m mentor_core.cli.evaluate $P --robot swarm --seed 1 --n 100000000
probe deep-world $PY -m mentor_core.cli.evaluate $P --robot swarm --world deep.yaml
probe deep-map $PY -m mentor_core.cli.evaluate $P --robot swarm --map deep.yaml
cp -r $U bag; echo "rosbag2_bagfile_information: $(python -c "print('['*600+']'*600)")" > bag/metadata.yaml
probe deep-bag $PY -m mentor_core.cli.evaluate $P --bag bag
probe bench-nothing $PY -m mentor_core.cli.bench --robot swarm --baselines none --no-oracle
mkdir run; echo "robot: swarm" > run/config.yaml; echo g > run/history.csv
mkdir empty
probe report-empty $PY -m mentor_core.cli.report empty --out rep1
probe report-into-run $PY -m mentor_core.cli.report empty --out run --force
probe dup-key timeout 20 $PY -m mentor_core.cli.train --robot swarm --framework dual --config dup.yaml --out r4
probe one_2 timeout 20 $PY -m mentor_core.cli.train --robot swarm --framework dual --config u.yaml --out r5
probe robot-mismatch timeout 20 $PY -m mentor_core.cli.train --robot swarm --framework dual --config r.yaml --out r6
"$PY" -c "
import json; d=json.load(open('$P')); d['metadata']['robot']='tank'; json.dump(d, open('tank.json','w'))"
probe genome-tank $PY -m mentor_core.cli.evaluate tank.json --bag $U
probe population timeout 20 $PY -m mentor_core.cli.train --robot swarm --framework dual --config quick --set evolution.population_size=100000000 --out r7
mkdir V; $PY -m mentor_core.cli.bench --robot swarm --families rooms --pairs-per-family 1 --baselines bug --no-oracle --out V >/dev/null 2>&1; sha=$(sha256sum V/bench.json)
probe bench-into-input $PY -m mentor_core.cli.bench --robot swarm --families rooms --pairs-per-family 1 --baselines bug --no-oracle --split test --baselines-chosen-on V/bench.json --out V
[ "$sha" == "$(sha256sum V/bench.json)" ] && echo "  V/bench.json unchanged" || echo "  V/bench.json REPLACED"
probe bench-existing $PY -m mentor_core.cli.bench --robot swarm --families rooms --pairs-per-family 1 --baselines bug --no-oracle --out V
probe bench-run-dir $PY -m mentor_core.cli.bench --robot swarm --families rooms --pairs-per-family 1 --baselines bug --no-oracle --out run
printf 'image: m.pgm\nresolution: 5e-2\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n' > m.yaml; printf 'P5 40 40 255\n' > m.pgm; python -c "open('m.pgm','ab').write(bytes([254])*1600)"
probe map-5e-2 $PY -m mentor_core.cli.evaluate $P --robot swarm --map m.yaml --n 2
cd /; rm -rf "$W"
