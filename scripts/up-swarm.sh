# shellcheck shell=bash disable=SC2154,SC2034  # sourced by scripts/up, whose variables it uses
# scripts/up --swarm (issue 35): the images into the registry, the plan, `docker stack deploy`.
#
#   swarm_deploy    after scripts/up built the images (testbed/<name>), or with --pushed (the
#                   images in the registry already); sets swarm_up=1 once the stack exists
#                   (scripts/up's cleanup then runs `docker stack rm testbed`)
#
# The images go to REGISTRY/testbed/<name>:latest. A registry on this host is pushed to as
# 127.0.0.1:PORT (dockerd trusts plain HTTP on loopback without configuration); the nodes pull
# the same repositories as ADDR:PORT, which their dockerd must list in insecure-registries
# (docs/scale-out.md, "Registry").

registry_has() {  # registry_has HOST:PORT REPOSITORY: its tag latest is there
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import json, sys, urllib.request
try:
    with urllib.request.urlopen(f"http://{sys.argv[1]}/v2/{sys.argv[2]}/tags/list", timeout=5) as r:
        sys.exit(0 if "latest" in (json.load(r).get("tags") or []) else 1)
except Exception:
    sys.exit(1)
EOF
}

registry_answers() {  # registry_answers HOST:PORT
  /usr/bin/python3 - "$1" <<'EOF'
import sys, urllib.request
try:
    urllib.request.urlopen(f"http://{sys.argv[1]}/v2/", timeout=3)
except Exception as e:
    sys.exit(1)
EOF
}

# Starts Debian's docker-registry on this host (port of REGISTRY) when none answers there.
ensure_registry() {  # ensure_registry HOST:PORT LOCAL(0|1)
  local reg=$1 local_reg=$2 port=${1##*:}
  registry_answers "$reg" && return 0
  if ((local_reg)); then
    registry_answers "127.0.0.1:$port" && return 0
    command -v docker-registry >/dev/null ||
      fail 1 "no registry answers at $reg and docker-registry is missing (Debian: docker-registry)"
    mkdir -p /var/lib/testbed-registry
    cat >"$logdir/registry.yml" <<EOF
version: 0.1
storage:
  filesystem:
    rootdirectory: /var/lib/testbed-registry
http:
  addr: :$port
EOF
    say "no registry answers at $reg: starting docker-registry on port $port (log" \
      "$logdir/registry.log; stopped again on exit)"
    setsid docker-registry serve "$logdir/registry.yml" >"$logdir/registry.log" 2>&1 </dev/null &
    registry_pid=$!
    local _
    for _ in $(seq 40); do
      registry_answers "127.0.0.1:$port" && return 0
      sleep 0.25
    done
    fail 1 "docker-registry did not answer on port $port (see $logdir/registry.log)"
  fi
  fail 1 "no registry answers at $reg (http://$reg/v2/): start one there (Debian's docker-registry)," \
    "or give --registry ADDR of one every node reaches"
}

swarm_deploy() {
  local manager addr reg push_to local_reg=0 name nodes known dir n
  manager=$(docker node inspect self --format '{{.Description.Hostname}}') ||
    fail 1 "docker node inspect self failed (above)"
  swarm_manager=$manager  # scripts/up's cleanup: the node whose volumes it can remove
  addr=$(docker info --format '{{.Swarm.NodeAddr}}')
  reg=${registry:-$addr:5000}
  [[ ${reg%%:*} == "$addr" || ${reg%%:*} == 127.0.0.1 || ${reg%%:*} == localhost ]] && local_reg=1
  local station_image=testbed/station
  if ((pushed)); then
    # The registry must answer and hold every image: a node that cannot pull one would wait
    # for it until UP_TIMEOUT.
    registry_answers "$reg" || fail 1 "--pushed: no registry answers at $reg (http://$reg/v2/)"
    for name in broker emulator station sim-server sim-client; do
      registry_has "$reg" "testbed/$name" ||
        fail 1 "--pushed: $reg has no testbed/$name:latest (push it first, e.g. tests/swarm/lab push)"
    done
    station_image=$reg/testbed/station:latest
  else
    ensure_registry "$reg" "$local_reg"
    push_to=$reg
    ((local_reg)) && push_to=127.0.0.1:${reg##*:}
    for name in broker emulator station sim-server sim-client; do
      say "pushing testbed/$name to $reg"
      { docker tag "testbed/$name" "$push_to/testbed/$name:latest" &&
        docker push "$push_to/testbed/$name:latest"; } >>"$logdir/push.log" 2>&1 ||
        fail 1 "pushing testbed/$name to $push_to failed ($(tail -n 1 "$logdir/push.log"); all in" \
          "$logdir/push.log)"
    done
  fi

  # The nodes: --nodes (each must be a node of this swarm), else every ready, active node.
  known=$(docker node ls --format '{{.Hostname}} {{.Status}} {{.Availability}}')
  local plan_opts=() given=""
  for ((n = 0; n < ${#swarm_opts[@]}; n += 2)); do
    [[ ${swarm_opts[n]} == --nodes ]] && given=${swarm_opts[n + 1]}
  done
  if [[ -n $given ]]; then
    for name in ${given//,/ }; do
      grep -q "^$name " <<<"$known" ||
        fail 2 "--nodes: unknown node '$name' (this swarm's nodes: $(awk '{print $1}' <<<"$known" | paste -sd' '))"
    done
  else
    nodes=$(awk '$2 == "Ready" && $3 == "Active" {print $1}' <<<"$known" | paste -sd,)
    plan_opts+=(--nodes "$nodes")
  fi
  dir=$logdir/swarm
  # A signing scenario's one PKI is made by its-pki from the station image (the host may have no
  # build of its own).
  mkdir -p "$dir"
  [[ -n ${TESTBED_TRACE_DIR:-} ]] && plan_opts+=(--trace-dir "$TESTBED_TRACE_DIR")
  "$root/scripts/swarm-plan" "$scenario" "${swarm_opts[@]}" "${plan_opts[@]}" --manager "$manager" \
    --registry "$reg" --out "$dir" \
    --its-pki "docker run --rm -v $dir:$dir --entrypoint /usr/local/bin/its-pki $station_image" ||
    fail 2 "the placement was refused (above); nothing started"

  swarm_up=1
  docker stack deploy -c "$dir/stack.yml" testbed 2>&1 | tee "$logdir/deploy.log"
  ((PIPESTATUS[0] == 0)) || fail 1 "docker stack deploy failed (above, and $logdir/deploy.log)"

  # Each service's log into the run's folder, from whichever node its tasks run on.
  local svc
  for svc in $(docker stack services testbed --format '{{.Name}}'); do
    docker service logs -f --raw "$svc" >"$logdir/${svc#testbed_}.log" 2>&1 &
    followers+=($!)
  done

  # Up once every node's emulator has its stations attached (it opens its ready port then).
  local emulators deadline missing
  emulators=$(/usr/bin/python3 -c 'import json, re, sys
for n in json.load(open(sys.argv[1]))["nodes"]:
    print(n["medium"].split(":")[0])' "$dir/placement.json")
  deadline=$((SECONDS + ${UP_TIMEOUT:-600}))
  while :; do
    missing=""
    for svc in $emulators; do
      grep -q "ready: TCP" "$logdir/$svc.log" 2>/dev/null || missing+=" $svc"
    done
    [[ -z $missing ]] && break
    if ((SECONDS > deadline)); then
      docker stack ps testbed --no-trunc --format '{{.Name}} {{.Node}} {{.CurrentState}} {{.Error}}' |
        head -n 40
      fail 1 "not up within ${UP_TIMEOUT:-600} s: waiting for${missing} (tasks above; logs in $logdir)"
    fi
    sleep 2 &
    wait $!
  done
  /usr/bin/python3 -c 'import json, sys
for n in json.load(open(sys.argv[1]))["nodes"]:
    ids = ",".join(map(str, n["stations"])) or "-"
    extra = ", %d pooled in %d station-host(s)" % (len(n["pooled"]), n["station_hosts"])
    print("[up] node %s: stations %s%s" % (n["name"], ids, extra if n["pooled"] else ""))' "$dir/placement.json"
  say "up: stack testbed on the swarm (manager $manager); placement $dir/placement.json; logs in $logdir"
  say "HMI: http://$addr:9001/ (the manager's address: the stack publishes the ports on the node" \
    "of their task, docs/scale-out.md), user hmi, password hmi"
  say "MQTT: mosquitto_sub -h $addr -p 1883 -u hmi -P hmi -t 'its/#' -v"
  say "tasks: docker stack ps testbed"
  for h in $humans; do
    say "drive '$h' from any computer that reaches the swarm: scripts/drive $addr --vehicle $h"
  done
}
