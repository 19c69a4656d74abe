#!/usr/bin/python3
"""Checks that the cluster's three forms run the same thing: the Compose file
(deploy/cluster/docker-compose.yml), the Kubernetes manifests (deploy/k8s/*.yaml) and the
network-namespace test (deploy/cluster/netns.sh).

    check_cluster.py [REPO_ROOT]

- Commands: the server's, viewer's and client's commands are the same word for word, except
  the address clients use (Compose's `lb`, the Kubernetes Service `mbstream`), the server
  pod's --advertise (its IP: other pods cannot resolve its name) and the viewer's
  --exit-after-runs (Compose's test follows one run; a Deployment follows forever);
  netns.sh passes the server the same options; images are the same.
- Ports: the server listens on 50051 (gRPC) and 9464 (metrics) in both; the Kubernetes
  container and Service declare both; the readiness probe and Compose health check ask
  `mbstream health` on that port.
- Secrets: every /run/secrets/NAME a container names is given to it (Compose `secrets:`,
  a Kubernetes secret volume item NAME mounted at /run/secrets); each Kubernetes key is a
  Compose secret of the same name, and create-secret.sh fills it from the same file.
Exit 0 when all hold, 1 (listing each problem) otherwise, 77 when PyYAML is missing.
"""
import os
import re
import sys

try:
    import yaml
except ImportError:
    print("check_cluster: SKIPPED: PyYAML is missing (Debian's python3-yaml)")
    sys.exit(77)

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), ".."))
CLUSTER = os.path.join(ROOT, "deploy", "cluster")
K8S = os.path.join(ROOT, "deploy", "k8s")
problems = []
checked = 0


def check(ok, message):
    global checked
    checked += 1
    if not ok:
        problems.append(message)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


compose = yaml.safe_load(read(os.path.join(CLUSTER, "docker-compose.yml")))
services = compose["services"]
k8s = {}  # (kind, name) -> document
for name in sorted(os.listdir(K8S)):
    if name.endswith(".yaml"):
        for doc in yaml.safe_load_all(read(os.path.join(K8S, name))):
            if doc:
                k8s[(doc["kind"], doc["metadata"]["name"])] = doc


def pod_spec(kind, name):
    doc = k8s.get((kind, name))
    check(doc is not None, "deploy/k8s: no %s %s" % (kind, name))
    return doc["spec"]["template"]["spec"] if doc else {"containers": [{}], "volumes": []}


def container(kind, name):
    spec = pod_spec(kind, name)
    return spec["containers"][0], spec


def secret_items(spec):
    """NAME -> key of the secret volume mounted at /run/secrets."""
    c = spec["containers"][0]
    mounts = {m["name"] for m in c.get("volumeMounts", []) if m["mountPath"] == "/run/secrets"}
    items = {}
    for v in spec.get("volumes", []):
        if v["name"] in mounts and "secret" in v:
            for item in v["secret"].get("items", []):
                items[item["path"]] = item["key"]
    return items


def secrets_named(value):
    return set(re.findall(r"/run/secrets/([A-Za-z0-9_]+)", yaml.safe_dump(value)))


def compose_env(service):
    env = service.get("environment", {})
    return env if isinstance(env, dict) else dict(e.split("=", 1) for e in env)


def k8s_env(c):
    """The literal variables (those from the downward API are checked where they are used)."""
    return {e["name"]: e["value"] for e in c.get("env", []) if "value" in e}


def with_pod_advertise(words):
    """A pod advertises its own IP (from the downward API): other pods cannot resolve its name."""
    return words + ["--advertise", "$(POD_IP):50051"]


def lb_to_service(words):
    return [w.replace("lb:50051", "mbstream:50051") for w in words]


def without_exit_after_runs(words):
    out, skip = [], False
    for w in words:
        if skip:
            skip = False
        elif w == "--exit-after-runs":
            skip = True
        else:
            out.append(w)
    return out


pairs = [  # compose service, k8s kind and name, how compose's command maps to k8s'
    ("server1", "Deployment", "mbstream-server", with_pod_advertise),
    ("viewer", "Deployment", "mbstream-viewer", lambda w: without_exit_after_runs(lb_to_service(w))),
    ("client", "Job", "mbstream-sweep", lambda w: w),
    ("postgres", "StatefulSet", "postgres", lambda w: w),
]
compose_secrets = compose["secrets"]
for service_name, kind, name, mapped in pairs:
    service = services[service_name]
    c, spec = container(kind, name)
    command = service.get("command") or []
    check(c.get("command") == mapped(command),
          "%s %s runs %s, compose %s runs %s" % (kind, name, c.get("command"), service_name,
                                                 mapped(command)))
    check(c.get("image") == service["image"],
          "%s %s image %s, compose %s" % (kind, name, c.get("image"), service["image"]))
    env = {k: v.replace("lb:50051", "mbstream:50051") for k, v in compose_env(service).items()}
    check(k8s_env(c) == env, "%s %s environment %s, compose %s" % (kind, name, k8s_env(c), env))
    # Secrets: named ones are given, same keys as compose's.
    given = set(service.get("secrets", []))
    for secret in secrets_named(service):
        check(secret in given, "compose %s names /run/secrets/%s but is not given it"
              % (service_name, secret))
    items = secret_items(spec)
    for secret in secrets_named(c):
        check(secret in items, "%s %s names /run/secrets/%s but mounts no such item"
              % (kind, name, secret))
    for path, key in items.items():
        check(path == key and key in compose_secrets,
              "%s %s mounts key %s as %s: keys are compose secret names, mounted as such"
              % (kind, name, key, path))
    check(set(items) == given, "%s %s is given secrets %s, compose %s %s"
          % (kind, name, sorted(items), service_name, sorted(given)))

# The server pod's POD_IP is its IP, from the downward API.
c, _ = container("Deployment", "mbstream-server")
pod_ip = [e for e in c.get("env", []) if e["name"] == "POD_IP"]
check(len(pod_ip) == 1 and pod_ip[0].get("valueFrom", {}).get("fieldRef", {}).get("fieldPath")
      == "status.podIP", "the server container's POD_IP is not the downward API's status.podIP")

# Ports of the server.
server = services["server1"]
words = server["command"]
listen_port = words[words.index("--listen") + 1].rsplit(":", 1)[1]
metrics_port = words[words.index("--metrics") + 1].rsplit(":", 1)[1]
c, _ = container("Deployment", "mbstream-server")
ports = {str(p["containerPort"]) for p in c.get("ports", [])}
check(ports == {listen_port, metrics_port},
      "the server container declares ports %s, its command listens on %s and %s"
      % (sorted(ports), listen_port, metrics_port))
service_doc = k8s.get(("Service", "mbstream"), {"spec": {"ports": []}})
check({str(p["port"]) for p in service_doc["spec"]["ports"]} == {listen_port, metrics_port},
      "the Service mbstream does not expose ports %s and %s" % (listen_port, metrics_port))
probe = c.get("readinessProbe", {}).get("exec", {}).get("command", [])
check(probe[:1] == ["mbstream"] and probe[-1:] == ["health"] and
      "localhost:" + listen_port in probe, "the readiness probe is not `mbstream health` on "
      "localhost:%s: %s" % (listen_port, probe))
check(server["healthcheck"]["test"][1:] == probe,
      "compose's health check %s differs from the readiness probe %s"
      % (server["healthcheck"]["test"][1:], probe))
for replica in ("server2", "server3"):
    check(services[replica] == server, "compose %s differs from server1" % replica)

# netns.sh gives the server the same options (its values are its own addresses and files).
netns = read(os.path.join(CLUSTER, "netns.sh"))
block = re.search(r'exec "\$\{srv_ns\[\$i\]\}" "\$server_bin" (.*?)>"\$out\.out"', netns, re.S)
check(block is not None, "deploy/cluster/netns.sh: no server command found")
store_args = re.search(r'store_args=\((--store "\$store_uri".*?)\)', netns)
check(store_args is not None, "deploy/cluster/netns.sh: no PostgreSQL store_args found")
if block and store_args:
    netns_options = set(re.findall(r"(--[a-z][a-z-]*)", block.group(1) + store_args.group(1)))
    compose_options = {w for w in words if w.startswith("--")}
    check(netns_options == compose_options, "netns.sh gives the server %s, compose %s"
          % (sorted(netns_options), sorted(compose_options)))

# create-secret.sh fills each key from the file compose reads for that secret.
create = read(os.path.join(K8S, "create-secret.sh"))
from_files = dict(re.findall(r'--from-file=([a-z_]+)="\$dir/([^"]+)"', create))
used = set().union(*(services[s].get("secrets", []) for s, _, _, _ in pairs))
for key in sorted(used):
    spec = compose_secrets[key]
    check(from_files.get(key) == os.path.basename(spec["file"]),
          "create-secret.sh fills %s from %s, compose from %s"
          % (key, from_files.get(key), spec["file"]))

if problems:
    for p in problems:
        print("check_cluster: " + p)
    print("check_cluster: %d of %d checks failed" % (len(problems), checked))
    sys.exit(1)
print("check_cluster: %d checks passed (compose, k8s and netns.sh agree)" % checked)
