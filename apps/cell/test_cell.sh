#!/usr/bin/env bash
# CTest driver for the simulated cell (registered in apps/cell/CMakeLists.txt).
# Usage:
#   test_cell.sh local  <mtc-cell>                 scripts over the in-memory link
#   test_cell.sh chuck  <mtc-cell>                 in-memory: OPEN_CHUCK withdrawn mid-motion
#   test_cell.sh transport <mtc-cell>              --transport: network by default, a bad kind exits 2
#   test_cell.sh dds    <mtc-cell> <domain>        3 processes over DDS, bounded run
#   test_cell.sh mixed  <mtc-cell> <domain>        the same with the robot on Cyclone DDS
#                                                   and the machine and feeder on Fast DDS
#   test_cell.sh mixedsecure <mtc-cell> <domain>  the same secured (a fresh test PKI), with
#                                                   the machine and the bridge (HTTP port
#                                                   5000 + domain) on Cyclone DDS: the sides
#                                                   that begin the authentications (see
#                                                   docs/security.md)
#   test_cell.sh commsloss <mtc-cell> <domain> <middleware>
#                                                   scenario 6: the robot and the feeder
#                                                   frozen in turn (SIGSTOP), each lost and
#                                                   recovered; <middleware> as --middleware
#                                                   takes it (fastdds, robot=cyclone)
#   test_cell.sh middleware <mtc-cell>             --middleware: bad names exit 2; in a
#                                                   build without Cyclone, cyclone too
#   test_cell.sh sigint <mtc-cell> <domain>        Ctrl-C stops every station, exit 0
#   test_cell.sh start  <build-dir> <domain> <port> scripts/start.sh: bridge serves the cell
#   test_cell.sh secure <build-dir> <domain> <port> the same with --secure: DDS-Security (a
#                                                   fresh test CA) and the bridge over HTTPS
# MTC_TEST_MIDDLEWARE=cyclone puts every station of modes dds and sigint on
# Cyclone DDS (as tests/support/transport.hpp does for the C++ tests).
# Runs inside the loopback-only namespace (the CMake entry wraps it in
# scripts/netns-run.sh, which is a no-op when ctest already runs inside one).
set -uo pipefail
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
mode="${1:-}"
case "$mode" in
  -h | --help) usage; exit 0 ;;
  local | chuck | transport | middleware) arguments=2 ;;
  dds | sigint | mixed | mixedsecure) arguments=3 ;;
  start | secure | commsloss) arguments=4 ;;
  *) echo "test_cell.sh: unknown mode or option '$mode'" >&2; usage >&2; exit 2 ;;
esac
if [ $# -ne "$arguments" ]; then
  echo "test_cell.sh: $mode takes $((arguments - 1)) argument(s)" >&2; usage >&2; exit 2
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT

fail() {
  echo "FAIL: $*" >&2
  echo "---- output ----" >&2
  cat "$log" >&2
  exit 1
}

expect() {  # expect <regex> <what>
  grep -Eq "$1" "$log" || fail "missing: $2 (/$1/)"
}

count() { grep -Ec "$1" "$log" || true; }

# Checks of a bounded run with a failure every 2nd cycle (seed 7).
check_bounded_run() {
  local cycles="$1"
  expect "cell summary: $cycles cycles complete" "all $cycles cycles"
  # Every handshake kind of the cell completed at least once.
  for s in MATERIAL_FEED MATERIAL_LOAD MATERIAL_UNLOAD OPEN_DOOR CLOSE_DOOR OPEN_CHUCK CLOSE_CHUCK; do
    expect "$s +done in .* both READY" "a completed $s handshake"
  done
  local injected late
  injected="$(count '!! .*injected failure')"
  [ "$injected" -ge $((cycles / 2)) ] || fail "expected >= $((cycles / 2)) injected failures, saw $injected"
  # A requester's fault (scenario 3) that a slow wake-up delivered after the
  # responder had finished changes nothing, and the station says so.
  late="$(count 'injected failure too late')"
  injected=$((injected - late))
  # The machine saw each one fail its step and recovered from every failure.
  local summary failures recovered
  summary="$(grep -E 'cell summary' "$log")"
  failures="$(sed -E 's/.* ([0-9]+) failures.*/\1/' <<<"$summary")"
  recovered="$(sed -E 's/.* ([0-9]+) recovered.*/\1/' <<<"$summary")"
  [ "$failures" -ge "$injected" ] || fail "machine saw $failures failures for $injected injected"
  [ "$failures" = "$recovered" ] || fail "$failures failures but $recovered recovered"
  # Each injected fault fails exactly one machine step, which the machine
  # attributes to its plan; nothing else may fail in a bounded run.
  local explained other
  explained="$(sed -nE 's/.*failures \(([0-9]+) injected, [0-9]+ other\).*/\1/p' <<<"$summary")"
  other="$(sed -nE 's/.*failures \([0-9]+ injected, ([0-9]+) other\).*/\1/p' <<<"$summary")"
  [ "$explained" = "$injected" ] ||
    fail "machine attributed '$explained' failures to $injected injected faults"
  [ "$other" = 0 ] || fail "'$other' failures not explained by an injected fault"
  expect "request recovered: FAIL -> READY" "a requester recovering"
  expect "response recovered -> READY" "a responder recovering"
  grep -Eq "UNRECOVERED|could not recover" "$log" && fail "a failure was not recovered"
  return 0
}

cell="$2"  # the mtc-cell executable (every mode but start and secure)
# The middleware of every station in modes dds and sigint: Fast DDS, or what
# MTC_TEST_MIDDLEWARE names (.ci/run's phase cyclone runs them on Cyclone).
middleware="${MTC_TEST_MIDDLEWARE:-fastdds}"
case "$mode" in
  transport)
    # The default comes from CellOptions, which the parser starts from.
    "$cell" --help >"$log" 2>&1 || fail "mtc-cell --help exited with $?"
    expect "loopback-udp \(default network\)" "the network as the default transport"
    rc=0
    "$cell" --transport pigeon --cycles 1 >"$log" 2>&1 || rc=$?
    [ "$rc" = 2 ] || fail "mtc-cell --transport pigeon exited with $rc, not 2"
    expect "unknown transport 'pigeon'" "the bad transport named" ;;
  local)
    timeout 120 "$cell" --transport loopback --local --cycles 10 --fail-every 2 --seed 7 --pace-ms 5 >"$log" 2>&1 ||
      fail "mtc-cell --local exited with $?"
    check_bounded_run 10
    # Ten cycles with one failure per two cycles take every fault point in turn.
    for scenario in 1 2 3; do
      expect "injected failure, scenario $scenario" "scenario $scenario injected"
    done ;;
  chuck)
    # Seed 17, one fault per cycle: cycle 1's fault is the robot's collision
    # at the chuck (scenario 3), injected half way through the chuck's
    # motion. The load retry comes back while the chuck is still UNLATCHED;
    # the chuck then stops OPEN and the machine's OPEN_CHUCK response stays
    # NOT_READY, so the robot must skip the step instead of waiting for READY
    # until the machine's load times out (15 s, counted as an 'other' failure).
    timeout 60 "$cell" --transport loopback --local --cycles 1 --fail-every 1 --seed 17 --pace-ms 100 >"$log" 2>&1 ||
      fail "mtc-cell --local exited with $?"
    expect "OPEN_CHUCK: injected failure, scenario 3" "the robot's collision at the chuck"
    expect "OPEN_CHUCK +request withdrawn" "the machine finishing a withdrawn OPEN_CHUCK"
    expect "OPEN_CHUCK +response recovered -> NOT_READY" "OPEN_CHUCK NOT_READY with the chuck OPEN"
    grep -Eq "could not raise" "$log" && fail "a request waited for a READY that never came"
    expect "cell summary: 1 cycles complete, [0-9]+ handshakes by the machine, 1 failures \\(1 injected, 0 other\\), 1 recovered" \
      "one injected failure, recovered, nothing else failing"
    expect "OPEN_CHUCK +skipped: already done" "the retried load skipping the opened chuck" ;;
  dds)
    timeout 150 "$cell" --transport loopback --middleware "$middleware" --cycles 6 --fail-every 2 \
      --seed 7 --pace-ms 10 --domain "$3" >"$log" 2>&1 ||
      fail "mtc-cell exited with $?"
    check_bounded_run 6
    expect "\(DDS domain $3, transport loopback, middleware $middleware\)" "the stations on the transport chosen"
    expect "all stations stopped, exit code 0" "a clean stop of every station" ;;
  mixed)
    # Issue 9 section 3: the wire contract is the IDL and the QoS, so every
    # handshake and injected failure of the cell completes across vendors.
    timeout 150 "$cell" --transport loopback --middleware robot=cyclone --cycles 6 --fail-every 2 \
      --seed 7 --pace-ms 10 --domain "$3" >"$log" 2>&1 ||
      fail "mtc-cell exited with $?"
    check_bounded_run 6
    expect "middleware machine fastdds, robot cyclone, feeder fastdds\)" "the robot on Cyclone"
    expect "robot +\| DDS middleware cyclone" "the robot's equipment built on Cyclone"
    expect "machine +\| DDS middleware fastdds" "the machine's equipment built on Fast DDS"
    expect "all stations stopped, exit code 0" "a clean stop of every station" ;;
  mixedsecure)
    # Issue 9 step 10: DDS-Security across vendors. Of the demo cell's
    # identities, cell-machine begins the authentication with the robot and
    # the feeder, and Fast DDS 2.9.1 answers Cyclone's ECDH; the other way
    # round Cyclone 0.10.2 cannot read Fast DDS's DH key and the pair never
    # meets (pinned in tests/security/test_cyclone_security.cpp).
    pki="$(mktemp -d)"
    trap 'rm -f "$log"; rm -rf "$pki"' EXIT
    "$root/scripts/security/make-pki.sh" --cell "$root/scripts/security/cell.txt" --out "$pki/cell" \
      >"$log" 2>&1 || fail "make-pki.sh exited with $?"
    # make-pki.sh's prediction of who begins: what the run below relies on.
    order="$(paste -sd' ' "$pki/cell/authentication-order.txt")"
    [[ "$order" == "mtc-bridge cell-machine "* ]] ||
      fail "authentication order '$order': the bridge and the machine do not begin"
    # The bridge on Cyclone too: mtc-bridge begins with every station.
    port=$((5000 + $3))
    : >"$pki/bridge.log"  # before tail reads it: the bridge starts in the background
    "$(dirname "$cell")/mtc-bridge" --transport loopback --domain-ids "$3" --port "$port" \
      --middleware cyclone --security "$pki/cell/mtc-bridge" >"$pki/bridge.log" 2>&1 &
    bridge_pid=$!
    timeout 30 grep -m1 -q "serving MTConnect" <(tail -n +1 -f "$pki/bridge.log") ||
      { kill "$bridge_pid"; cat "$pki/bridge.log" >"$log"; fail "the bridge did not start"; }
    timeout 150 "$cell" --transport loopback --middleware machine=cyclone --security "$pki/cell" \
      --cycles 6 --fail-every 2 --seed 7 --pace-ms 10 --domain "$3" >"$log" 2>&1 ||
      { kill "$bridge_pid"; fail "mtc-cell exited with $?"; }
    current="$(curl -sf "http://127.0.0.1:$port/current")" || { kill "$bridge_pid"; fail "no /current"; }
    kill -INT "$bridge_pid"
    wait "$bridge_pid" || fail "mtc-bridge exited with $? after SIGINT"
    cat "$pki/bridge.log" >>"$log"
    for station in machine robot feeder; do
      grep -q "uuid=\"cell-$station\"" <<<"$current" || fail "the bridge did not see cell-$station"
    done
    check_bounded_run 6
    expect "machine +\| DDS middleware cyclone" "the machine's equipment built on Cyclone"
    expect "robot +\| DDS middleware fastdds" "the robot's equipment built on Fast DDS"
    if grep -q "handshake reply failed" "$log"; then
      fail "an authentication failed between the middlewares"
    fi
    expect "all stations stopped, exit code 0" "a clean stop of every station" ;;
  commsloss)
    # Freezes start 4-12 s apart and last lease + 3 s, the robot's first: 45 s
    # hold the robot's and the feeder's, and 14 s or more after the second
    # (a third may be cut short by the end of the run).
    timeout 100 "$cell" --transport loopback --middleware "$4" --duration 45 --fail-every 0 \
      --seed 7 --pace-ms 20 --comms-loss-every 8 --domain "$3" >"$log" 2>&1 ||
      fail "mtc-cell exited with $?"
    for station in robot feeder; do
      expect "cell +\| !! $station frozen \(SIGSTOP\)" "the $station frozen"
      expect "cell +\| $station resumes after" "the $station resumed"
      expect "machine +\| link .* -> cell-$station: LOST" "the machine losing the $station"
      expect "machine +\| link .* -> cell-$station: UP" "the machine hearing the $station again"
    done
    # Each freeze failed the step in progress, if any, and every failure
    # recovered; nothing was injected by the plan (--fail-every 0).
    summary="$(grep -E 'cell summary' "$log")" || fail "no cell summary"
    grep -Eq "0 failures|failures \(0 injected" <<<"$summary" || fail "plan failures in: $summary"
    failures="$(sed -E 's/.* ([0-9]+) failures.*/\1/' <<<"$summary")"
    recovered="$(sed -E 's/.* ([0-9]+) recovered.*/\1/' <<<"$summary")"
    # A freeze the stop cut short (no "resumes" after its "frozen") may leave
    # its one failure unrecovered: the machine recovers 2 s after the loss.
    cut_short="$(awk '/ frozen \(SIGSTOP\)/ { f = NR } /resumes after/ { r = NR } END { print (f > r) }' "$log")"
    if [ "$failures" != "$recovered" ]; then
      { [ "$cut_short" = 1 ] && [ "$failures" = $((recovered + 1)) ]; } ||
        fail "$failures failures but $recovered recovered"
    fi
    grep -Eq "UNRECOVERED|could not recover" "$log" && fail "a failure was not recovered"
    # The cell kept working once both stations had come back.
    awk '/resumes after/ && ++resumed == 2 { back = NR } /=== cycle [0-9]+ complete/ { last = NR }
         END { exit !(back && last > back) }' "$log" || fail "no cycle completed after the second resume"
    if [ "$4" = robot=cyclone ]; then
      expect "robot +\| DDS middleware cyclone" "the robot's equipment built on Cyclone"
    fi
    expect "all stations stopped, exit code 0" "a clean stop of every station" ;;
  middleware)
    "$cell" --help >"$log" 2>&1 || fail "mtc-cell --help exited with $?"
    expect "middleware STATION=NAME" "the option in the help"
    for bad in "opendds:unknown middleware 'opendds'" "robot=opendds:unknown middleware 'opendds'" \
      "arm=fastdds:unknown station in --middleware 'arm=fastdds'"; do
      rc=0
      "$cell" --transport loopback --middleware "${bad%%:*}" --cycles 1 >"$log" 2>&1 || rc=$?
      [ "$rc" = 2 ] || fail "mtc-cell --middleware ${bad%%:*} exited with $rc, not 2"
      expect "${bad#*:}" "the bad value named"
    done
    if [ "${MTC_CELL_HAS_CYCLONE:-}" = 0 ]; then
      rc=0
      "$cell" --transport loopback --middleware robot=cyclone --cycles 1 >"$log" 2>&1 || rc=$?
      [ "$rc" = 2 ] || fail "mtc-cell --middleware robot=cyclone exited with $rc without Cyclone"
      expect "configure with -DMTC_CYCLONE=ON" "the CMake switch named"
    fi ;;
  sigint)
    "$cell" --transport loopback --middleware "$middleware" --pace-ms 10 --domain "$3" >"$log" 2>&1 &
    pid=$!
    # Block until the first cycle is through (an event in the output, no sleep).
    timeout 60 grep -m1 -q "cycle 1 complete" <(tail -n +1 -f "$log") ||
      { kill -KILL "$pid"; fail "no cycle completed"; }
    stations="$(grep -Eo 'pid [0-9]+' "$log" | awk '{print $2}')"
    kill -INT "$pid"
    rc=0
    timeout 30 tail --pid="$pid" -f /dev/null || { kill -KILL "$pid"; fail "not stopped in 30 s"; }
    wait "$pid" || rc=$?
    [ "$rc" = 0 ] || fail "exit code $rc after SIGINT"
    for p in $stations; do
      kill -0 "$p" 2>/dev/null && fail "station pid $p still running"
    done
    expect "stop requested: stopping every station" "the stop being handed to the stations"
    expect "all stations stopped, exit code 0" "every station stopped" ;;
  start | secure)
    build="$2" domain="$3" port="$4"
    state="$(mktemp -d)"
    secure=() scheme=http tls=()
    if [ "$mode" = secure ]; then
      secure=(--secure) scheme=https tls=(--cacert "$state/pki/https/cert.pem")
    fi
    MTC_BUILD_DIR="$build" MTC_CELL_STATE_DIR="$state" MTC_PKI_DIR="$state/pki" \
      "$root/scripts/start.sh" --no-build "${secure[@]}" --domain "$domain" --port "$port" \
      --pace-ms 10 >"$log" 2>&1 &
    pid=$!
    timeout 60 grep -m1 -q "cycle 1 complete" <(tail -n +1 -f "$log") ||
      { kill -TERM "$pid"; fail "no cycle completed"; }
    # The bridge learns each device from its announcement, which may reach it
    # after the stations' first cycle: poll /current until every device and
    # item is there (or 30 s pass) instead of judging the first answer.
    needles=('uuid="cell-machine"' 'uuid="cell-robot"' 'uuid="cell-feeder"'
             '<MaterialLoad' '<OpenDoor' '<DoorState' '<ChuckState' '<MaterialFeed')
    has_all() { for n in "${needles[@]}"; do grep -q "$n" <<<"$current" || return 1; done; }
    current="" deadline=$((SECONDS + 30))
    until has_all; do
      [ "$SECONDS" -lt "$deadline" ] || break
      current="$(curl -sS --max-time 10 "${tls[@]}" "$scheme://127.0.0.1:$port/current")" ||
        { kill -TERM "$pid"; fail "bridge did not answer /current"; }
      has_all || sleep 0.2
    done
    if [ "$mode" = secure ]; then
      expect "DDS-Security: on" "start.sh announcing DDS-Security"
      curl -s --max-time 5 -o /dev/null "http://127.0.0.1:$port/current" &&
        { kill -TERM "$pid"; fail "the secured bridge answered plain HTTP"; }
    fi
    kill -TERM "$pid"
    rc=0
    wait "$pid" || rc=$?
    [ -e "$state/mtc-cell.netns.pid" ] && fail "start.sh left its pid file behind"
    rm -rf "$state/pki"
    rmdir "$state"
    [ "$rc" = 0 ] || fail "start.sh exit code $rc after SIGTERM"
    for needle in "${needles[@]}"; do
      grep -q "$needle" <<<"$current" || { echo "$current" >>"$log"; fail "/current lacks $needle"; }
    done
    expect "cell stopped \(exit code 0\)" "start.sh reporting a clean stop" ;;
esac
echo "ok: $mode"
