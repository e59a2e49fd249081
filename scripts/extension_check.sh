#!/usr/bin/env bash
# Issue 53's acceptance made literal: a new history quantity is its
# declaration plus its computation, 2 files, and reaches history.csv, the
# response figure's panels and the lab with no third file. In a scratch copy
# of the committed tree (git worktree, under build/, removed at exit) this
# applies a patch that adds one quantity (tests/extension/new_quantity.patch,
# or the patch given as the first argument), checks that it touches exactly
# the schema's file (rocking.quantities) and the file of rocking.simulation's
# evaluate, builds the program and the lab's server plugin it loads
# (rocking_cli; the quick preset, without LTO or PGO), and checks with that
# program:
#   - `rocking simulate`: history.csv has the quantity's column, "NAME [unit]",
#     and, for the shipped patch's v_N = du_N/dt, its values agree with the
#     central differences of u_N (the relative RMS difference below 2 %);
#   - `rocking plot response`: the gnuplot script draws that column by name,
#     column('NAME [unit]') times the schema's display factor (the reading of
#     tests/figure_schema_test.cpp);
#   - `rocking serve` on a free localhost port, a run POSTed to /api/simulate:
#     the answer's columns list the quantity with its unit, display unit and
#     the schema's factor, and its history holds its values.
# What the patch declares (name, unit, display factor and unit) is read from
# the table entry it adds. Exit 0 when the quantity reached every place; 1,
# with one line for each place it did not reach (or the step that failed).
# Run from the repository: bash scripts/extension_check.sh [PATCH]
set -uo pipefail

root=$(git rev-parse --show-toplevel) || exit 1
patch=$(realpath "${1:-$root/tests/extension/new_quantity.patch}")
started=$(date +%s)
[ -d "$root/.tools/bin" ] && export PATH="$root/.tools/bin:$PATH"

mkdir -p "$root/build"
scratch=$(mktemp -d "$root/build/extension-check.XXXXXX")
tree=$scratch/tree
server=""
cleanup() {
  [ -n "$server" ] && kill "$server" 2>/dev/null && wait "$server" 2>/dev/null
  git -C "$root" worktree remove --force "$tree" >/dev/null 2>&1
  rm -rf "$scratch"
}
trap cleanup EXIT

failures=()
fail() { failures+=("$1"); echo "extension check: $1" >&2; }
finish() {
  echo "extension check: $(($(date +%s) - started)) s"
  if [ ${#failures[@]} -gt 0 ]; then
    echo "extension check FAILED: ${#failures[@]} problem(s):" >&2
    printf '  %s\n' "${failures[@]}" >&2
    exit 1
  fi
  echo "extension check passed: $name reaches history.csv, the response figure and the lab, from 2 files"
  exit 0
}
# A step without which nothing after it can be checked.
stop() { fail "$1"; finish; }

# 1. The scratch copy of the committed tree.
git -C "$root" worktree add --quiet --detach "$tree" HEAD || stop "git worktree add $tree failed"

# 2. The patch, and the files it changed: the schema's and evaluate's, nothing else.
[ -f "$patch" ] || stop "$patch: no such patch"
git -C "$tree" apply "$patch" || stop "$(basename "$patch") does not apply to the committed tree"
schema_file=$(cd "$tree" && grep -rl --include='*.cppm' '^export module rocking.quantities;' modules)
evaluate_file=$(cd "$tree" && grep -rl --include='*.cpp' '^Response evaluate(' modules/simulation)
changed=$(git -C "$tree" diff --stat=200 | sed '$d' | awk '{print $1}' | sort)
expected=$(printf '%s\n%s\n' "$schema_file" "$evaluate_file" | sort)
if [ "$changed" != "$expected" ]; then
  stop "the patch changes $(echo $changed | tr ' ' ',') (git diff --stat); a new quantity is its declaration ($schema_file) and its computation ($evaluate_file) only"
fi

# What the patch declares: the one quantity_table entry it adds.
IFS=$'\t' read -r name unit factor display_unit < <(python3 - "$patch" <<'EOF'
import re, sys
added = "".join(l[1:] for l in open(sys.argv[1]).read().splitlines(True) if l.startswith("+") and not l.startswith("+++"))
entries = re.findall(r'\{Quantity::\w+,\s*"([^"]*)",\s*"([^"]*)",\s*"[^"]*",\s*"[^"]*",\s*([^,]+?),\s*"([^"]*)"', added)
if len(entries) != 1:
    sys.exit(f"{len(entries)} quantity_table entries added")
n, u, f, d = entries[0]
if not re.fullmatch(r"[0-9eE.+\-*/ ()]+", f):
    sys.exit(f"figure factor '{f}' is not a number")
print(n, u, f"{float(eval(f)):.17g}", d, sep="\t")
EOF
) || stop "the patch must add exactly one entry to quantity_table"
header="$name [$unit]"
[ -z "$unit" ] && header=$name
echo "extension check: $(basename "$patch") adds $name [$unit], drawn x$factor in $display_unit; building in $tree"

# 3. The program and the plugins it loads (rocking serve's), nothing else.
log=$root/build/extension-check.log
if ! (cd "$tree" && cmake --preset quick >"$log" 2>&1 && cmake --build --preset quick --target rocking_cli >>"$log" 2>&1); then
  stop "the patched tree does not build (the log: $log)"
fi
bin=$tree/build-quick/bin/rocking
out=$scratch/out

# 4a. rocking simulate: the column, with its unit, and (v_N) its values.
"$bin" simulate --every 0.0002 --out "$out/simulate" >"$scratch/simulate.log" 2>&1 ||
  fail "rocking simulate failed: $(tail -1 "$scratch/simulate.log")"
history=$(python3 - "$out/simulate/history.csv" "$header" "$name" 2>"$scratch/history.err" <<'EOF'
import csv, math, sys
path, header, name = sys.argv[1:4]
try:
    rows = list(csv.reader(open(path)))
except OSError:
    sys.exit("history.csv (rocking simulate) was not written")
head = rows[0]
if header not in head:
    sys.exit(f"history.csv (rocking simulate) has no column '{header}' (columns: {', '.join(head)})")
if name == "v_N":
    # The shipped patch: v_N against u_N's central differences over rows
    # 0.2 ms apart, away from phase changes (an impact changes the elastic
    # velocities at once). Their error, (2 pi f h)^2 / 6, is 0.06 % for the
    # chimney's fourth fixed-base mode (48 Hz): a wrong velocity is off by
    # its order, v_N is within 2 %.
    k, u, t, p = head.index(header), head.index("u_N [m]"), head.index("t [s]"), head.index("phase")
    data = [(float(r[t]), float(r[u]), float(r[k]), r[p]) for r in rows[1:]]
    diff = norm = 0.0
    for (t0, u0, _, p0), (t1, _, v1, p1), (t2, u2, _, p2) in zip(data, data[1:], data[2:]):
        if t2 - t0 > 1e-9 and p0 == p1 == p2:
            diff += ((u2 - u0) / (t2 - t0) - v1) ** 2
            norm += v1 ** 2
    ratio = math.sqrt(diff / norm) if norm > 0 else math.inf
    print(f"v_N against du_N/dt by central differences: relative RMS difference {ratio:.3%} over {len(data)} rows")
    if not ratio < 0.02:
        sys.exit(f"history.csv's v_N differs from du_N/dt by {ratio:.2%} RMS (at most 2 %)")
EOF
) || fail "$(tail -1 "$scratch/history.err")"
[ -n "$history" ] && echo "extension check: $history"

# 4b. rocking plot response: the script draws the column by name, in the figure's unit.
"$bin" plot response --variants scene --formats png --out "$out/plot" >"$scratch/plot.log" 2>&1 ||
  fail "rocking plot response failed: $(tail -1 "$scratch/plot.log")"
script=$out/plot/response.gp
drawn=$(python3 -c "import sys; print(f\"column('{sys.argv[1]}')*{float(sys.argv[2]):.9g}\")" "$header" "$factor")
if [ ! -f "$script" ]; then
  fail "rocking plot response wrote no $script"
elif ! grep -qF "column('$header')" "$script"; then
  fail "the response figure (rocking plot response) does not draw $name: no column('$header') in its gnuplot script"
elif ! grep -qF "$drawn" "$script"; then
  fail "the response figure draws $name, but not as $drawn (the schema's display factor)"
fi

# 4c. rocking serve: a run POSTed, the lab's columns and history. The page's
# scripts from npm (lab/node_modules, not committed) are the repository's.
[ -d "$root/lab/node_modules" ] || stop "$root/lab/node_modules is missing (make setup installs it): rocking serve needs it"
ln -s "$root/lab/node_modules" "$tree/lab/node_modules"
"$bin" serve --port 0 >"$scratch/serve.log" 2>&1 &
server=$!
port=""
for _ in $(seq 1 100); do
  port=$(grep -o 'http://127.0.0.1:[0-9]*' "$scratch/serve.log" 2>/dev/null | head -1 | sed 's/.*://')
  [ -n "$port" ] && break
  sleep 0.1
done
if [ -z "$port" ]; then
  fail "rocking serve printed no address: $(tail -1 "$scratch/serve.log")"
else
  lab=$(python3 - "$port" "$name" "$unit" "$factor" "$display_unit" <<'EOF'
import json, sys, urllib.request
port, name, unit, factor, display_unit = sys.argv[1:6]
request = urllib.request.Request(f"http://127.0.0.1:{port}/api/simulate", data=b"{}",
                                 headers={"Content-Type": "application/json"})
try:
    answer = json.load(urllib.request.urlopen(request, timeout=300))
except Exception as e:
    print(f"POST /api/simulate failed: {e}"); sys.exit()
columns = [c for c in answer.get("columns", []) if c.get("name") == name]
if not columns:
    print(f"the lab's answer (POST /api/simulate) lists no column {name} (columns: "
          + ", ".join(c.get("name", "?") for c in answer.get("columns", [])) + ")"); sys.exit()
c = columns[0]
said = []
if c.get("unit") != unit: said.append(f"unit '{c.get('unit')}', not '{unit}'")
if c.get("display_unit") != display_unit: said.append(f"display unit '{c.get('display_unit')}', not '{display_unit}'")
if not isinstance(c.get("factor"), (int, float)) or abs(c["factor"] - float(factor)) > 1e-12 * abs(float(factor)):
    said.append(f"factor {c.get('factor')}, not the schema's {float(factor):g}")
if c.get("use") not in ("chart", "drawn"): said.append(f"use '{c.get('use')}'")
values = answer.get("history", {}).get(name)
if not values or not any(v not in (None, 0) for v in values): said.append("no values in the answer's history")
if said: print(f"the lab lists {name} with " + "; ".join(said))
EOF
)
  [ -n "$lab" ] && fail "$lab"
fi

finish
