#!/usr/bin/env python3
"""scripts/swarm-plan (issue 35): placement and stack file for a Docker Swarm, and its refusals.

    python3 tests/launcher/swarm_plan_test.py      (ctest launcher.swarm_plan, label unit)

Runs the planner as a user would, on the scenarios under scenarios/, and checks its output
against the scenario files as this test reads them (not against what the planner prints): every
station on exactly one node, the dealing, the label placement, the stack's services, pins and
replicas, and that the stack passes the v3 schema check of docker.io 20.10's `docker stack
deploy` (run against no daemon: it checks the file first; 20.10 has no `docker stack config`)
and Debian's docker-compose's; the broker takes the planned logins; a signing scenario's ATs made
on two nodes from the root and AA the plan ships chain to the same AA (its-pki from the build;
skipped without it). No Docker daemon is used.
"""
import json
import shutil
import subprocess
import tempfile
import unittest
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
PLAN = ROOT / "scripts" / "swarm-plan"
SCEN = ROOT / "scenarios"


def stations_of(path):
    """(full, pooled) station ids of a scenario, read here independently of the planner."""
    doc = json.loads(Path(path).read_text())
    pooled = [v["station_id"] for v in doc["vehicles"]
              if (v.get("station") or {}).get("kind") == "pooled"]
    full = [v["station_id"] for v in doc["vehicles"] if v["station_id"] not in pooled]
    return full + [r["station_id"] for r in doc.get("rsus", [])], pooled


class SwarmPlan(unittest.TestCase):
    def setUp(self):
        self.tmp = Path(tempfile.mkdtemp(prefix="swarm-plan-"))
        self.out = self.tmp / "out"

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def run_plan(self, scenario, *args, expect=0, out=None):
        out = out or self.out
        r = subprocess.run([str(PLAN), str(scenario), *args, "--out", str(out)],
                           capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, expect, r.stdout + r.stderr)
        if expect != 0:
            # Refused before anything starts: nothing written.
            self.assertFalse(out.exists(), "a refused plan wrote files")
        return r

    def placement(self):
        return json.loads((self.out / "placement.json").read_text())

    def stack(self):
        return yaml.safe_load((self.out / "stack.yml").read_text())

    def labels(self, labels):
        f = self.tmp / "labels.json"
        f.write_text(json.dumps(labels))
        return str(f)

    def assert_every_station_once(self, scenario, place):
        full, pooled = stations_of(scenario)
        got_full = [s for n in place["nodes"] for s in n["stations"]]
        got_pooled = [s for n in place["nodes"] for s in n["pooled"]]
        self.assertEqual(sorted(got_full), sorted(full))
        self.assertEqual(sorted(got_pooled), sorted(pooled))

    # ---- dealing ---------------------------------------------------------------------------------
    def test_round_robin_deals_in_turn(self):
        self.run_plan(SCEN / "demo.json", "--nodes", "a,b")
        place = self.placement()
        self.assert_every_station_once(SCEN / "demo.json", place)
        by = {n["name"]: n for n in place["nodes"]}
        self.assertEqual(by["a"]["stations"], [1001, 1003])
        self.assertEqual(by["b"]["stations"], [1002, 1004])
        self.assertEqual(by["a"]["medium"], "emulator-a:4730")
        self.assertEqual(by["a"]["station_hosts"], 0)

    def test_round_robin_pooled_and_rsus(self):
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2,n3", "--station-hosts", "2")
        place = self.placement()
        self.assert_every_station_once(SCEN / "dense-ring.json", place)
        totals = [len(n["stations"]) + len(n["pooled"]) for n in place["nodes"]]
        self.assertLessEqual(max(totals) - min(totals), 1, totals)
        for n in place["nodes"]:
            self.assertEqual(n["station_hosts"], min(2, len(n["pooled"])))
        # A road-side unit is a full station like a vehicle's.
        self.run_plan(SCEN / "signals-junction.json", "--nodes", "a,b", out=self.tmp / "o2")
        place = json.loads((self.tmp / "o2" / "placement.json").read_text())
        self.assertIn(5001, [s for n in place["nodes"] for s in n["stations"]])
        self.assertEqual([n["pooled"] for n in place["nodes"]], [[], []])

    def test_more_nodes_than_stations_leaves_nodes_out(self):
        self.run_plan(SCEN / "lcrw-frontal.json", "--nodes", "a,b,c")
        place = self.placement()
        self.assertEqual([n["name"] for n in place["nodes"]], ["a", "b"])
        self.assertNotIn("emulator-c", self.stack()["services"])

    def test_by_label(self):
        lab = self.labels({"a": {"testbed.stations": "3001,3003-3030"},
                           "b": {"testbed.stations": "3002, 3031-3060", "other": "x"}})
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "a,b", "--by", "label", "--labels", lab)
        place = self.placement()
        self.assert_every_station_once(SCEN / "dense-ring.json", place)
        by = {n["name"]: n for n in place["nodes"]}
        self.assertEqual(by["a"]["stations"], [3001])
        self.assertEqual(sorted(by["a"]["pooled"]), list(range(3003, 3031)))
        self.assertEqual(sorted(by["b"]["pooled"]), list(range(3031, 3061)))

    # ---- refusals --------------------------------------------------------------------------------
    def test_label_leaves_station_without_node(self):
        lab = self.labels({"a": {"testbed.stations": "1001"}, "b": {"testbed.stations": "1002,1003"}})
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a,b", "--by", "label", "--labels", lab,
                          expect=2)
        self.assertIn("station 1004 has no node", r.stderr)
        self.assertIn("demo.json", r.stderr)

    def test_label_station_twice(self):
        lab = self.labels({"a": {"testbed.stations": "1001-1003"}, "b": {"testbed.stations": "1003,1004"}})
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a,b", "--by", "label", "--labels", lab,
                          expect=2)
        self.assertIn("node b, label testbed.stations: station 1003 is already placed on node a",
                      r.stderr)

    def test_label_unknown_node(self):
        lab = self.labels({"a": {"testbed.stations": "1001-1004"}, "zz": {"testbed.stations": "1"}})
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a,b", "--by", "label", "--labels", lab,
                          expect=2)
        self.assertIn("unknown node 'zz'", r.stderr)

    def test_label_bad_value_and_foreign_station(self):
        lab = self.labels({"a": {"testbed.stations": "1001,x7"}})
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a", "--by", "label", "--labels", lab,
                          expect=2)
        self.assertIn("node a, label testbed.stations: 'x7' is not a station id", r.stderr)
        lab = self.labels({"a": {"testbed.stations": "1001-1005"}})
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a", "--by", "label", "--labels", lab,
                          expect=2)
        self.assertIn("station 1005 is not in", r.stderr)

    def test_realtime_off_and_bad_values(self):
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2", "--realtime-priority", "0")
        for name in ("n1", "n2"):
            emu = self.stack()["services"][f"emulator-{name}"]
            self.assertEqual(sorted(emu["cap_add"]), ["NET_ADMIN", "SYS_ADMIN"])
            self.assertNotIn("TESTBED_RT_PRIORITY", emu["environment"])
            self.assertNotIn("TESTBED_RT_RUNTIME_US", emu["environment"])
        shutil.rmtree(self.out)
        for opt, bad, says in (("--realtime-priority", "100", "a SCHED_FIFO priority 1..99"),
                               ("--realtime-priority", "-1", "a SCHED_FIFO priority 1..99"),
                               ("--realtime-runtime", "0", "µs per second, 1..1000000"),
                               ("--realtime-runtime", "1000001", "µs per second, 1..1000000")):
            r = self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2", opt, bad, expect=2)
            self.assertIn(f"{opt}: {bad}: {says}", r.stderr)

    def test_empty_node_list(self):
        for nodes in ("", " , "):
            r = self.run_plan(SCEN / "demo.json", "--nodes", nodes, expect=2)
            self.assertIn("--nodes: the node list is empty", r.stderr)

    def test_node_named_twice(self):
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a,b,a", expect=2)
        self.assertIn("node a named twice", r.stderr)
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a.lab,a-lab", expect=2)
        self.assertIn("would share the service names", r.stderr)

    def test_bad_scenario(self):
        bad = self.tmp / "bad.json"
        bad.write_text(json.dumps({"vehicles": [{"id": "x", "station_id": "7"}]}))
        r = self.run_plan(bad, "--nodes", "a", expect=2)
        self.assertIn("bad.json: /vehicles/0/station_id", r.stderr)
        bad.write_text(json.dumps({"vehicles": [{"station_id": 7}], "rsus": [{"station_id": 7}]}))
        r = self.run_plan(bad, "--nodes", "a", expect=2)
        self.assertIn("/rsus/0/station_id: station 7 appears twice", r.stderr)
        r = self.run_plan(self.tmp / "missing.json", "--nodes", "a", expect=2)
        self.assertIn("missing.json: cannot read", r.stderr)

    def test_labels_only_with_label(self):
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a", "--labels", self.labels({}), expect=2)
        self.assertIn("--labels: only with --by label", r.stderr)

    # ---- the stack -------------------------------------------------------------------------------
    def test_stack_pins_and_replicas(self):
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2,n3", "--manager", "n2",
                      "--registry", "10.77.0.1:5000")
        place, st = self.placement(), self.stack()
        services = st["services"]
        self.assertEqual(st["version"], "3.8")
        for n in place["nodes"]:
            name = n["name"]
            for svc, replicas in ((f"emulator-{name}", 1), (f"station-{name}", len(n["stations"])),
                                  (f"station-host-{name}", n["station_hosts"])):
                self.assertIn(svc, services)
                d = services[svc]["deploy"]
                self.assertEqual(d["replicas"], replicas, svc)
                self.assertEqual(d["placement"]["constraints"], [f"node.hostname == {name}"], svc)
            for svc in (f"emulator-{name}", f"station-{name}", f"station-host-{name}"):
                # A swarm restarts an unhealthy task: no check counts while a node comes up.
                self.assertEqual(services[svc]["healthcheck"], {"start_period": "600s"}, svc)
            emu = services[f"emulator-{name}"]
            self.assertEqual(sorted(emu["cap_add"]), ["NET_ADMIN", "SYS_ADMIN", "SYS_NICE"])
            # The medium at real-time priority, and its cgroup's budget (scale-out.md).
            self.assertEqual(emu["environment"]["TESTBED_RT_PRIORITY"], "50")
            self.assertEqual(emu["environment"]["TESTBED_RT_RUNTIME_US"], "400000")
            self.assertEqual(emu["environment"]["TESTBED_NODE"], name)
            self.assertEqual(emu["environment"]["STATION_HOSTS"], str(n["station_hosts"]))
            # Weighted above the stations, which keep the runtime's 1024 (scale-out.md).
            self.assertGreater(int(emu["environment"]["TESTBED_CPU_SHARES"]), 1024)
            for svc in (f"station-{name}", f"station-host-{name}"):
                self.assertNotIn("TESTBED_CPU_SHARES", services[svc]["environment"], svc)
                self.assertNotIn("TESTBED_RT_PRIORITY", services[svc]["environment"], svc)
                self.assertNotIn("cap_add", services[svc], svc)
            # The node's stations and its emulator share the attach volume, and only they.
            attach = f"attach-{name}:/run/testbed-attach"
            users = sorted(s for s, v in services.items() if attach in v.get("volumes", []))
            self.assertEqual(users, sorted([f"emulator-{name}", f"station-{name}",
                                            f"station-host-{name}"]))
        for svc in ("broker", "sim-server", "driver"):
            self.assertEqual(services[svc]["deploy"]["placement"]["constraints"],
                             ["node.hostname == n2"])
        # The manager's emulator is the one address; it relays to every other node's.
        self.assertEqual(services["emulator-n2"]["environment"]["TESTBED_RELAY"].split(","),
                         ["emulator-n1:4700", "emulator-n3:4700"])
        self.assertNotIn("TESTBED_RELAY", services["emulator-n1"]["environment"])
        self.assertIn("emulator-n2:4700", services["driver"]["command"])
        for svc, v in services.items():
            self.assertTrue(v["image"].startswith("10.77.0.1:5000/testbed/"), svc)
            self.assertTrue(v["image"].endswith(":latest"), svc)
            for key in ("build", "scale", "depends_on", "container_name"):
                self.assertNotIn(key, v, f"{svc} has {key}")
            # No virtual IP or ingress mesh: they need IPVS, which some kernels lack.
            self.assertEqual(v["deploy"]["endpoint_mode"], "dnsrr", svc)
            for p in v.get("ports", []):
                self.assertEqual(p["mode"], "host", svc)
        self.assertEqual(sorted((p["published"], p["protocol"]) for p in services["broker"]["ports"]),
                         [(1883, "tcp"), (9001, "tcp")])
        self.assertEqual(sorted((p["published"], p["protocol"])
                                for p in services["emulator-n2"]["ports"]),
                         [(4700, "udp"), (4701, "udp")])
        # Configs and the secret name files that exist beside the stack.
        for section in ("configs", "secrets"):
            for key, c in st[section].items():
                self.assertTrue((self.out / c["file"]).is_file(), f"{section}.{key}")
        self.assertEqual(json.loads((self.out / st["configs"]["placement"]["file"]).read_text()),
                         place)
        creds = json.loads((self.out / "mqtt-credentials.json").read_text())
        full, pooled = stations_of(SCEN / "dense-ring.json")
        self.assertEqual(sorted(map(int, creds["stations"])), sorted(full + pooled))
        self.assertEqual(creds["hosts"]["station-host"]["stations"], pooled)

    def test_trace_dir_in_emulators_and_stations(self):
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2", "--trace-dir", "/tmp/tr")
        services = self.stack()["services"]
        traced = {n for n, s in services.items() if "TESTBED_TRACE_DIR" in s.get("environment", {})}
        want = {f"{kind}-{n}" for kind in ("emulator", "station", "station-host") for n in ("n1", "n2")}
        self.assertEqual(traced, want)
        for n in want:
            self.assertEqual(services[n]["environment"]["TESTBED_TRACE_DIR"], "/tmp/tr")
        # Without the option no service traces (the trace files cost disk in the containers).
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2", out=self.tmp / "o2")
        st = yaml.safe_load((self.tmp / "o2" / "stack.yml").read_text())
        self.assertFalse([n for n, s in st["services"].items()
                          if "TESTBED_TRACE_DIR" in s.get("environment", {})])
        r = self.run_plan(SCEN / "demo.json", "--nodes", "a", "--trace-dir", "tr", expect=2,
                          out=self.tmp / "o3")
        self.assertIn("--trace-dir: 'tr' must be an absolute path", r.stderr)

    def test_manager_without_stations(self):
        self.run_plan(SCEN / "lcrw-frontal.json", "--nodes", "a,b", "--manager", "boss")
        services = self.stack()["services"]
        self.assertEqual(services["broker"]["deploy"]["placement"]["constraints"],
                         ["node.hostname == boss"])
        self.assertIn("emulator-a:4700", services["driver"]["command"])
        self.assertEqual(services["emulator-a"]["environment"]["TESTBED_RELAY"], "emulator-b:4700")

    def test_opendrive_map_travels_with_the_scenario(self):
        self.run_plan(SCEN / "four-way-junction.json", "--nodes", "a,b")
        st = self.stack()
        self.assertEqual((self.out / st["configs"]["map"]["file"]).read_bytes(),
                         (SCEN / "maps" / "four_way_junction.xodr").read_bytes())
        targets = [c["target"] for c in st["services"]["sim-server"]["configs"]]
        self.assertIn("/testbed/scenarios/maps/four_way_junction.xodr", targets)
        self.assertIn("/testbed/scenarios/four-way-junction.json", targets)

    def test_broker_takes_the_planned_logins(self):
        if shutil.which("mosquitto_passwd") is None:
            self.skipTest("mosquitto_passwd (Debian's mosquitto) not installed")
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2")
        gen = ROOT / "docker/mosquitto/gen-broker-config"
        creds = self.out / "mqtt-credentials.json"
        r = subprocess.run([str(gen), "--scenario", str(SCEN / "dense-ring.json"), "--credentials",
                            str(creds), "--out", str(self.tmp / "broker")],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        made = json.loads((self.tmp / "broker/credentials.json").read_text())
        planned = json.loads(creds.read_text())
        for section in ("stations", "hosts", "readers"):
            self.assertEqual(made[section], planned[section], section)
        self.assertEqual((self.tmp / "broker/stations/3001.password").read_text().strip(),
                         planned["stations"]["3001"]["password"])
        # Logins made for another scenario are refused, naming the station.
        r = subprocess.run([str(gen), "--scenario", str(SCEN / "demo.json"), "--credentials",
                            str(creds), "--out", str(self.tmp / "broker2")],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("/stations/1001/password: missing", r.stderr)

    def signed_scenario(self):
        doc = json.loads((SCEN / "lcrw-three-vehicles.json").read_text())
        doc["security"] = "signed"
        doc["vehicles"][2]["station"] = {"pki": "foreign"}
        path = self.tmp / "signed.json"
        path.write_text(json.dumps(doc))
        return path

    def its_pki(self):
        tool = Path(ROOT / "build/release/bin/its-pki")
        if not tool.is_file():
            self.skipTest("its-pki not built (cmake --build build/release --target its-pki)")
        return tool

    def test_signed_scenario_one_pki_for_all_nodes(self):
        tool = self.its_pki()
        scenario = self.signed_scenario()
        self.run_plan(scenario, "--nodes", "a,b,c", "--its-pki", str(tool))
        st = self.stack()
        for name in ("signed", "signed-foreign"):
            for f in ("root.cert", "root.pem", "aa.cert", "aa.pem"):
                key = f"pki-{name}-{f}"
                self.assertIn(key, st["secrets"])
                self.assertTrue((self.out / st["secrets"][key]["file"]).is_file(), key)
                for svc in ("station-a", "station-host-b"):
                    self.assertIn({"source": key, "target": key}, st["services"][svc]["secrets"])
        self.assertEqual(st["services"]["station-c"]["environment"]["PKI_SEED"], "/run/secrets")
        # The world's check: ATs made on two nodes from the shipped root and AA (as the station
        # entry point does: seed, then its-pki make) chain to the same AA.
        issuers = []
        for node, sid in (("a", "1001"), ("b", "1002")):
            d = self.tmp / f"node-{node}" / "signed"
            d.mkdir(parents=True)
            for f in ("root.cert", "root.pem", "aa.cert", "aa.pem"):
                shutil.copyfile(self.out / "pki/signed" / f, d / f)
            subprocess.run([str(tool), "make", "--dir", str(d), "--name", "signed", "--station",
                            sid], check=True, capture_output=True)
            self.assertEqual((d / "root.cert").read_bytes(),
                             (self.out / "pki/signed/root.cert").read_bytes(), "root made anew")
            shown = subprocess.run([str(tool), "show", str(d / f"at-{sid}.cert")],
                                   capture_output=True, text=True, check=True).stdout
            issuers.append([l for l in shown.splitlines() if l.startswith("issuer:")])
        aa = subprocess.run([str(tool), "show", str(self.out / "pki/signed/aa.cert")],
                            capture_output=True, text=True, check=True).stdout
        aa_id = [l.split()[1] for l in aa.splitlines() if l.startswith("hashedId8:")]
        self.assertEqual(len(aa_id), 1, aa)
        self.assertEqual(issuers, [[f"issuer: {aa_id[0]}"]] * 2)

    def test_signed_scenario_without_its_pki(self):
        r = self.run_plan(self.signed_scenario(), "--nodes", "a", "--its-pki",
                          str(self.tmp / "no-such-its-pki"), expect=2)
        self.assertIn("--its-pki: '" + str(self.tmp / "no-such-its-pki") + "' not found", r.stderr)
        r = self.run_plan(self.signed_scenario(), "--nodes", "a", "--its-pki", "", expect=2)
        self.assertIn("signed.json: /security: the scenario signs (signed)", r.stderr)

    def station_entrypoint(self, **env):
        """docker/station/entrypoint as a module, its paths in this test's folder."""
        import importlib.machinery
        import importlib.util
        import os
        saved = dict(os.environ)
        os.environ.update({"TESTBED_RUN_DIR": str(self.tmp / "run"), **env})
        try:
            loader = importlib.machinery.SourceFileLoader(
                "station_entrypoint", str(ROOT / "docker/station/entrypoint"))
            spec = importlib.util.spec_from_loader(loader.name, loader)
            module = importlib.util.module_from_spec(spec)
            loader.exec_module(module)
        finally:
            os.environ.clear()
            os.environ.update(saved)
        return module

    def test_station_reads_its_login_from_the_secret(self):
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1")
        creds = self.out / "mqtt-credentials.json"
        planned = json.loads(creds.read_text())
        st = self.station_entrypoint(MQTT_CREDENTIALS=str(creds),
                                     BROKER_CONFIG=str(self.tmp / "no-broker-volume"))
        entry, pw = st.login("stations", "3001", "credentials for station 3001")
        self.assertEqual(entry["username"], "station-3001")
        self.assertEqual(pw.read_text().strip(), planned["stations"]["3001"]["password"])
        self.assertEqual(pw.stat().st_mode & 0o777, 0o600)
        entry, pw = st.login("hosts", "station-host", "station-host login")
        self.assertEqual(pw.read_text().strip(), planned["hosts"]["station-host"]["password"])
        with self.assertRaises(SystemExit) as e:  # another scenario's secret
            st.login("stations", "1001", "credentials for station 1001")
        self.assertEqual(e.exception.code, 1)

    def test_station_seeds_the_shared_pki(self):
        tool = self.its_pki()
        scenario = self.signed_scenario()
        self.run_plan(scenario, "--nodes", "a", "--its-pki", str(tool))
        seed = self.tmp / "secrets"
        seed.mkdir()
        for f in ("root.cert", "root.pem", "aa.cert", "aa.pem"):
            shutil.copyfile(self.out / "pki/signed" / f, seed / f"pki-signed-{f}")
        import os
        self.addCleanup(os.environ.__setitem__, "PATH", os.environ["PATH"])
        os.environ["PATH"] = f"{tool.parent}:{os.environ['PATH']}"  # its-pki, as in the image
        st = self.station_entrypoint(SCENARIO=str(scenario), PKI_DIR=str(self.tmp / "pki"),
                                     PKI_SEED=str(seed))
        # A volume left with another deployment's root: replaced by the shared one.
        (self.tmp / "pki/signed").mkdir(parents=True)
        (self.tmp / "pki/signed/root.cert").write_bytes(b"old")
        self.assertEqual(st.security_args("1002", []), ["--pki-dir", str(self.tmp / "pki/signed")])
        self.assertEqual((self.tmp / "pki/signed/root.cert").read_bytes(),
                         (self.out / "pki/signed/root.cert").read_bytes())
        self.assertTrue((self.tmp / "pki/signed/at-1002.cert").is_file())
        # Without the seed's files the station refuses rather than trust a root of its own.
        st = self.station_entrypoint(SCENARIO=str(scenario), PKI_DIR=str(self.tmp / "pki2"),
                                     PKI_SEED=str(self.tmp / "empty"))
        with self.assertRaises(SystemExit):
            st.security_args("1002", [])

    def test_stack_passes_docker_stack_deploy_schema(self):
        # Debian's docker.io 20.10 has no `docker stack config`, but `stack deploy` checks the file
        # against its v3 schema before it talks to any daemon: with no daemon to reach, a file
        # that passes fails only at the connection.
        tool = "/usr/bin/docker" if Path("/usr/bin/docker").exists() else shutil.which("docker")
        if tool is None:
            self.skipTest("no docker CLI")
        self.run_plan(SCEN / "four-way-junction.json", "--nodes", "n1,n2")
        env = {"PATH": "/usr/bin:/bin", "DOCKER_HOST": f"unix://{self.tmp}/no-daemon.sock",
               "HOME": str(self.tmp)}

        def deploy(name):
            return subprocess.run([tool, "stack", "deploy", "-c", str(self.out / name), "testbed"],
                                  capture_output=True, text=True, cwd=self.out, env=env,
                                  timeout=60)
        r = deploy("stack.yml")
        self.assertIn("Cannot connect to the Docker daemon", r.stderr)
        self.assertNotIn("is not allowed", r.stderr)
        text = (self.out / "stack.yml").read_text().replace("    cap_add:", "    cap_addd:", 1)
        (self.out / "bad.yml").write_text(text)
        r = deploy("bad.yml")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("Additional property cap_addd is not allowed", r.stderr)

    def test_stack_is_valid_compose(self):
        tool = shutil.which("docker-compose")
        if tool is None:
            self.skipTest("docker-compose (Debian's) not installed: no schema check")
        self.run_plan(SCEN / "dense-ring.json", "--nodes", "n1,n2")
        r = subprocess.run([tool, "-f", str(self.out / "stack.yml"), "config", "-q"],
                           capture_output=True, text=True, cwd=self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        # The check can fail: a key the schema does not know is refused.
        text = (self.out / "stack.yml").read_text().replace("    cap_add:", "    cap_addd:", 1)
        (self.out / "bad.yml").write_text(text)
        r = subprocess.run([tool, "-f", str(self.out / "bad.yml"), "config", "-q"],
                           capture_output=True, text=True, cwd=self.out)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("cap_addd", r.stderr)


FAKE_DOCKER = """#!/bin/sh
# docker info --format '{{.Swarm.LocalNodeState}} {{.Swarm.ControlAvailable}}'
[ "$1" = info ] && { echo "$FAKE_SWARM"; exit 0; }
echo "fake docker: unexpected $*" >&2; exit 99
"""


class UpSwarm(unittest.TestCase):
    """scripts/up --swarm's refusals, before anything is installed, built or started."""

    def run_up(self, *args, swarm_state="inactive false"):
        with tempfile.TemporaryDirectory() as d:
            (Path(d) / "docker").write_text(FAKE_DOCKER)
            (Path(d) / "docker").chmod(0o755)
            env = {"PATH": f"{d}:/usr/bin:/bin:/usr/sbin:/sbin", "FAKE_SWARM": swarm_state}
            return subprocess.run([str(ROOT / "scripts/up"), *args], capture_output=True,
                                  text=True, env=env, timeout=60)

    def setUp(self):
        import os
        if os.geteuid() != 0:
            self.skipTest("scripts/up checks for root first")

    def test_not_a_manager(self):
        for state in ("inactive false", "active false"):
            r = self.run_up("--swarm", "demo", swarm_state=state)
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertIn("this host's Docker is not a swarm manager", r.stderr)
            self.assertIn(f"swarm state: {state}", r.stderr)
            self.assertIn("docker swarm init", r.stderr)
            self.assertNotIn("fake docker: unexpected", r.stderr)

    def test_swarm_options_need_swarm(self):
        r = self.run_up("demo", "--nodes", "a,b")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--nodes, --by, --registry, --pushed, --station-hosts and "
                      "--realtime-priority go with --swarm", r.stderr)
        r = self.run_up("demo", "--realtime-priority", "50")
        self.assertEqual(r.returncode, 2)
        self.assertIn("go with --swarm", r.stderr)
        r = self.run_up("demo", "--pushed")
        self.assertEqual(r.returncode, 2)
        self.assertIn("go with --swarm", r.stderr)
        r = self.run_up("--swarm", "demo", "--pushed")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--pushed needs --registry ADDR", r.stderr)
        r = self.run_up("--swarm", "demo", "--by")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--by needs a value", r.stderr)


if __name__ == "__main__":
    unittest.main()
