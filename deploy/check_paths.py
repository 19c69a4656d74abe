#!/usr/bin/python3
"""Checks that the docker-compose demo names only things that exist, without Docker.

    check_paths.py [REPO_ROOT]

No Docker engine runs on our machines, so this stands in for building the images:
- deploy/Dockerfile: its build context is what deploy/stage.sh stages: every COPY source is
  a file stage.sh puts there, from a repo path that exists, or one of the programs stage.sh
  copies from the build (each an add_executable of its folder's CMakeLists.txt) or the
  package lists it writes; every repo script a RUN line names exists; the stages the compose
  file asks for exist.
- deploy/docker-compose.yml: each service's command starts with a program its image
  installs; every /opt/mbstream path it names maps to a repo path through a COPY (or to
  one a build stage made, COPY --from); every
  /run/secrets/NAME is a secret the service is given; every secret file is one that
  deploy/make-secrets.sh writes.
- Commands stay identical to the multi-host test: for each program, the options the compose
  file passes are the options deploy/multihost/run.sh passes, and each is an option the
  program's source declares; the client's environment is one run.sh sets too.
Exit 0 when all hold, 1 (listing each problem) otherwise, 77 when PyYAML is missing.
Standard library plus PyYAML (Debian's python3-yaml, a dependency of docker-compose).
"""
import os
import re
import shlex
import sys

try:
    import yaml
except ImportError:
    print("check_paths: SKIPPED: PyYAML is missing (scripts/setup.sh installs docker-compose, "
          "which brings python3-yaml)")
    sys.exit(77)

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), ".."))
DEPLOY = os.path.join(ROOT, "deploy")
problems = []
checked = 0


def check(ok, message):
    global checked
    checked += 1
    if not ok:
        problems.append(message)


def repo(path):
    return os.path.join(ROOT, path)


def logical_lines(text):
    """Joins backslash continuations and drops comments."""
    lines, current = [], ""
    for raw in text.splitlines():
        line = raw.rstrip()
        if not current and line.lstrip().startswith("#"):
            continue
        if line.endswith("\\"):
            current += line[:-1] + " "
            continue
        current += line
        if current.strip():
            lines.append(current.strip())
        current = ""
    return lines


# Where each program's command-line options are declared, and which Debian package brings
# programs that are not ours.
SOURCES = {
    "mbstream-server": ["server/app"],
    "mbstream-viewer": ["viewer/app"],
    "mbstream": ["client/cli"],
}
DEBIAN_PROGRAMS = {"xvfb-run": "xvfb", "bash": None}


def declared_options(program):
    text = ""
    for d in SOURCES[program]:
        for name in sorted(os.listdir(repo(d))):
            if name.endswith((".cc", ".h")):
                with open(repo(os.path.join(d, name))) as f:
                    text += f.read()
    return set(re.findall(r'"(--[a-z][a-z0-9-]*)"', text))


# ---- the staged build context (deploy/stage.sh) ------------------------------------------
with open(os.path.join(DEPLOY, "stage.sh")) as f:
    stage_script = f.read()
# Staged path -> repo path, for what stage.sh copies from the checkout.
STAGED = {"web": "viewer/web", "demo-client.sh": "deploy/demo-client.sh",
          "models/irb1600": "models/irb1600", "Dockerfile": "deploy/Dockerfile"}
for staged, source in STAGED.items():
    check(os.path.exists(repo(source)), f"stage.sh: {source} is not in the repo")
    check(os.path.basename(source) in stage_script, f"stage.sh does not stage {source} (as {staged})")
# The programs stage.sh copies from the build: BUILD_DIR/<dir>/<name>.
staged_programs = {}
for d, exe in re.findall(r"(?<![\w$/])((?:server|client|viewer)(?:/\w+)*)/(mbstream[\w-]*)", stage_script):
    staged_programs[exe] = d
for exe, d in staged_programs.items():
    cmake = repo(os.path.join(d, "CMakeLists.txt"))
    ok = os.path.isfile(cmake) and re.search(
        r"add_executable\(\s*" + re.escape(exe) + r"[\s)]", open(cmake).read())
    check(bool(ok), f"stage.sh: {d}/{exe}: {d}/CMakeLists.txt has no add_executable({exe})")


def staged_source(src):
    """The repo path a staged COPY source comes from; "" for a build product; None if unstaged."""
    src = src.rstrip("/")
    if src in STAGED:
        return STAGED[src]
    if src.startswith("bin/") and os.path.basename(src) in staged_programs:
        return ""
    if src.endswith(".packages") and f'"$stage/{src}"' in stage_script:
        return ""
    return None


def default_of(value):
    """A compose value with ${VAR:-default} or ${VAR-default} substitutions, as defaulted."""
    return re.sub(r"\$\{\w+:?-([^}]*)\}", r"\1", str(value))


# ---- Dockerfile --------------------------------------------------------------------------
dockerfile = os.path.join(DEPLOY, "Dockerfile")
with open(dockerfile) as f:
    docker_lines = logical_lines(f.read())

stages = {}  # name -> {"base": str, "programs": set, "paths": {image_path: repo_path}, "apt": set}
stage = None
for line in docker_lines:
    word, _, rest = line.partition(" ")
    word = word.upper()
    if word == "FROM":
        m = re.match(r"(\S+)(?:\s+AS\s+(\S+))?", rest, re.I)
        base, name = m.group(1), m.group(2) or m.group(1)
        parent = stages.get(base)
        stage = {"base": base,
                 "programs": set(parent["programs"]) if parent else set(),
                 "paths": dict(parent["paths"]) if parent else {},
                 "apt": set(parent["apt"]) if parent else set()}
        stages[name] = stage
    elif word == "COPY":
        args = shlex.split(rest)
        from_stage = None
        while args and args[0].startswith("--"):
            if args[0].startswith("--from="):
                from_stage = args[0].split("=", 1)[1]
            args = args[1:]
        *sources, dest = args
        for src in sources:
            if from_stage:
                check(from_stage in stages, f"Dockerfile: COPY --from={from_stage}: no such stage")
                if src.startswith("/out/bin/"):
                    check(dest.rstrip("/") == "/usr/local/bin",
                          f"Dockerfile: {src} is not copied to /usr/local/bin")
                    stage["programs"].add(os.path.basename(src))
                elif dest.startswith("/opt/mbstream/"):
                    stage["paths"][dest.rstrip("/")] = None  # made by that stage's RUN
                continue
            source = staged_source(src)
            check(source is not None, f"Dockerfile: COPY source {src} is not something deploy/stage.sh stages")
            if source is None:
                continue
            check(source == "" or os.path.exists(repo(source)),
                  f"Dockerfile: COPY source {src} ({source}) is not in the repo")
            target = dest if not dest.endswith("/") else os.path.join(dest, os.path.basename(src))
            stage["paths"][target.rstrip("/")] = source or None
            if target.startswith("/usr/local/bin/"):
                stage["programs"].add(os.path.basename(target))
                check(source == "" or os.access(repo(source), os.X_OK),
                      f"Dockerfile: {src} ({source}) is not executable")
    elif word == "RUN":
        for script in re.findall(r"(?<![\w/])((?:scripts|deploy)/[\w./-]+\.(?:sh|py))", rest):
            check(os.path.isfile(repo(script)), f"Dockerfile: RUN names {script}, not in the repo")
            check(os.access(repo(script), os.X_OK), f"Dockerfile: {script} is not executable")
        for d, exe in re.findall(r"/build/([\w/]+)/([\w.-]+)(?=[\s;&]|$)", rest):
            cmake = repo(os.path.join(d, "CMakeLists.txt"))
            ok = os.path.isfile(cmake) and re.search(
                r"add_executable\(\s*" + re.escape(exe) + r"[\s)]", open(cmake).read())
            check(bool(ok), f"Dockerfile: /build/{d}/{exe}: {d}/CMakeLists.txt has no "
                            f"add_executable({exe})")
        for m in re.finditer(r"apt-get install[^&]*", rest):
            stage["apt"].update(w for w in m.group(0).split() if re.fullmatch(r"[a-z0-9][a-z0-9.+-]+", w))

# ---- compose file -------------------------------------------------------------------------
compose_path = os.path.join(DEPLOY, "docker-compose.yml")
with open(compose_path) as f:
    compose = yaml.safe_load(f)
with open(os.path.join(DEPLOY, "make-secrets.sh")) as f:
    make_secrets = f.read()

for name, spec in (compose.get("secrets") or {}).items():
    path = default_of(spec.get("file", ""))
    check(path.startswith("./secrets/"), f"compose: secret {name} is not under ./secrets/")
    check(re.search(r'"\$out/' + re.escape(os.path.basename(path)) + '"', make_secrets) is not None,
          f"compose: secret {name} ({path}) is not a file make-secrets.sh writes")

compose_commands = {}  # program -> (options, env)
for service, spec in compose["services"].items():
    build = spec.get("build") or {}
    context = os.path.normpath(os.path.join(DEPLOY, default_of(build.get("context", "."))))
    check(context == os.path.join(DEPLOY, "stage"),
          f"compose: {service}: build context is not deploy/stage (what deploy/stage.sh stages)")
    check(STAGED.get(build.get("dockerfile", "Dockerfile")) == "deploy/Dockerfile",
          f"compose: {service}: Dockerfile {build.get('dockerfile')} is not the one stage.sh stages")
    target = build.get("target")
    check(target in stages, f"compose: {service}: Dockerfile has no stage {target}")
    st = stages.get(target, {"programs": set(), "paths": {}, "apt": set()})
    command = spec.get("command")
    check(isinstance(command, list) and command, f"compose: {service}: command is not a list")
    words = list(command)
    # Unwrap `xvfb-run -a PROGRAM ...`.
    while words and words[0] in DEBIAN_PROGRAMS:
        package = DEBIAN_PROGRAMS[words[0]]
        check(package is None or package in st["apt"],
              f"compose: {service}: {words[0]} needs Debian's {package} in stage {target}")
        words = words[1:]
        while words and words[0].startswith("-") and not words[0].startswith("--"):
            words = words[1:]
    program = words[0] if words else ""
    check(program in st["programs"], f"compose: {service}: {program} is not installed by "
                                     f"stage {target} (it has {sorted(st['programs'])})")
    given = set(spec.get("secrets") or [])
    env = spec.get("environment") or {}
    for value in words + [str(v) for v in env.values()]:
        for secret in re.findall(r"/run/secrets/([\w.-]+)", value):
            check(secret in given, f"compose: {service}: uses secret {secret} it is not given")
        if value.startswith("/opt/mbstream/"):
            mapped = None
            for image_path, src in st["paths"].items():
                if value == image_path or value.startswith(image_path + "/"):
                    mapped = "" if src is None else src + value[len(image_path):]
            check(mapped == "" or (mapped is not None and os.path.exists(repo(mapped))),
                  f"compose: {service}: {value} is not in image {target} (no COPY gives it)")
    compose_commands[program] = ({w for w in words if w.startswith("--")}, set(env))

# ---- the same commands as the multi-host test ---------------------------------------------
with open(os.path.join(DEPLOY, "multihost", "run.sh")) as f:
    run_lines = logical_lines(f.read())
MULTIHOST_VAR = {"mbstream-server": "$server_bin", "mbstream-viewer": "$viewer_bin",
                 "demo-client.sh": "deploy/demo-client.sh"}
for program, (options, env) in compose_commands.items():
    var = MULTIHOST_VAR.get(program)
    check(var is not None, f"multihost: compose runs {program}, which run.sh does not")
    if var is None:
        continue
    line = next((l for l in run_lines if var in l and "ip netns exec" in l), None)
    check(line is not None, f"multihost: run.sh never runs {program} on a host")
    if line is None:
        continue
    after = line[line.index(var):]
    run_options = set(re.findall(r"(?<!\S)(--[a-z][a-z0-9-]*)", after))
    check(options == run_options,
          f"multihost: {program}: compose passes {sorted(options)}, run.sh {sorted(run_options)}")
    if program in SOURCES:
        missing = options - declared_options(program)
        check(not missing, f"{program} declares no option {sorted(missing)}")
    run_env = set(re.findall(r"\b(MBSTREAM_[A-Z_]+)=", line))
    check(env <= run_env, f"multihost: {program}: compose sets {sorted(env - run_env)}, run.sh not")
# demo-client.sh's own CLI calls use options the CLI declares.
with open(os.path.join(DEPLOY, "demo-client.sh")) as f:
    client_options = set(re.findall(r"(?<!\S)(--[a-z][a-z0-9-]*)", f.read()))
missing = client_options - declared_options("mbstream")
check(not missing, f"demo-client.sh: mbstream declares no option {sorted(missing)}")

if problems:
    print(f"check_paths: FAIL: {len(problems)} of {checked} checks")
    for p in problems:
        print("  " + p)
    sys.exit(1)
print(f"check_paths: OK: {checked} checks over deploy/Dockerfile, deploy/docker-compose.yml, "
      f"deploy/multihost/run.sh ({len(stages)} stages, {len(compose['services'])} services)")
