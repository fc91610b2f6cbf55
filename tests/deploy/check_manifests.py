#!/usr/bin/env python3
"""Reads the Dockerfile, .dockerignore, deploy/compose.yaml and deploy/k8s/roomrender.yaml and checks
what no engine on the test machine can run: the image builds from every tracked source file, runs as
uid 10001 with a data directory it owns (the single-container embedded store) and serves its
schemas; compose and Kubernetes run PostgreSQL on a volume of its own and point every stateless
replica at it, and their nginx upstreams name those replicas. One PASS/FAIL line per check; exit 1 on any
failure. Usage: tests/deploy/check_manifests.py [SOURCE_DIR]   (python3 and python3-yaml)
"""
import os
import re
import shlex
import subprocess
import sys

import yaml

RUNTIME_UID = 10001
RUNTIME_USER = "roomrender"

failures = []


def check(name, ok, why=""):
    print(f"check_manifests: {'PASS' if ok else 'FAIL'} {name}{'' if ok else ': ' + why}")
    if not ok:
        failures.append(name)


# --- Dockerfile -------------------------------------------------------------------------------------

def dockerfile_stages(text):
    """Instructions per stage: [(stage_name, [(KEYWORD, argument text)])], continuation lines joined."""
    joined = re.sub(r"\\\n", " ", text)
    stages = []
    for line in joined.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        keyword, _, rest = line.partition(" ")
        keyword = keyword.upper()
        if keyword == "FROM":
            m = re.search(r"\bAS\s+(\S+)", rest, re.IGNORECASE)
            stages.append((m.group(1) if m else str(len(stages)), []))
        elif stages:
            stages[-1][1].append((keyword, rest.strip()))
    return stages


def env_values(instructions):
    env = {}
    for keyword, rest in instructions:
        if keyword == "ENV":
            for token in shlex.split(rest):
                if "=" in token:
                    key, value = token.split("=", 1)
                    env[key] = value
    return env


def check_dockerfile(source_dir):
    stages = dockerfile_stages(open(os.path.join(source_dir, "Dockerfile")).read())
    check("Dockerfile has two stages, build and runtime", [s[0] for s in stages] == ["build", "runtime"],
          f"stages {[s[0] for s in stages]}")
    if len(stages) != 2:
        return None
    build, runtime = stages[0][1], stages[1][1]
    runs = " ".join(rest for keyword, rest in build if keyword == "RUN")
    check("build stage copies the whole context (COPY . .)", ("COPY", ". .") in build,
          "a fixed folder list misses folders added later")
    check("build stage compiles with -Werror and runs the unit tests",
          "-DROOMRENDER_WERROR=ON" in runs and re.search(r"build/tests/unit_tests\b(?! *--gtest_list)", runs)
          and "--target roomrender unit_tests" in runs, runs)

    env = env_values(runtime)
    copied = {}  # destination -> source of COPY --from=build
    for keyword, rest in runtime:
        parts = rest.split()
        if keyword == "COPY" and parts and parts[0] == "--from=build":
            copied[parts[-1]] = parts[1]
    runtime_runs = " ".join(rest for keyword, rest in runtime if keyword == "RUN")
    users = [rest for keyword, rest in runtime if keyword == "USER"]
    check(f"runtime user {RUNTIME_USER} has uid and gid {RUNTIME_UID}",
          re.search(rf"useradd\b[^&]*--uid {RUNTIME_UID} --gid {RUNTIME_UID}\b[^&]*\b{RUNTIME_USER}\b",
                    runtime_runs) is not None
          and users and users[-1] in (RUNTIME_USER, str(RUNTIME_UID)), f"USER {users}")
    for name, source in [("WEB", "/src/clients/web"), ("EXAMPLES", "/src/examples"), ("SCHEMAS", "/src/schemas"),
                         ("CATALOGUE", "/src/catalogue")]:
        var = f"ROOMRENDER_{name}_DIR"
        value = env.get(var)
        check(f"{var} names where the image holds {source}", value is not None and copied.get(value) == source,
              f"{var}={value}, copies {copied}")

    data_dir = env.get("ROOMRENDER_DATA_DIR")
    check("ROOMRENDER_DATA_DIR is set", data_dir is not None, "the server would keep scenes in memory only")
    if data_dir is None:
        return None
    owned = re.search(rf"install -d -o {RUNTIME_USER} -g {RUNTIME_USER}\b[^&]*\s{re.escape(data_dir)}\b",
                      runtime_runs) or re.search(rf"chown\b[^&]*\b{RUNTIME_USER}\b[^&]*\s{re.escape(data_dir)}\b",
                                                 runtime_runs)
    check(f"the image creates {data_dir} owned by {RUNTIME_USER}", owned is not None, runtime_runs)
    volumes = [rest for keyword, rest in runtime if keyword == "VOLUME"]
    check(f"VOLUME {data_dir}", any(data_dir in v for v in volumes), f"VOLUME {volumes}")
    health = " ".join(rest for keyword, rest in runtime if keyword == "HEALTHCHECK")
    check("HEALTHCHECK on /livez, STOPSIGNAL SIGTERM",
          "/livez" in health and ("STOPSIGNAL", "SIGTERM") in runtime, health)
    return data_dir


# --- .dockerignore ----------------------------------------------------------------------------------

def ignore_regex(pattern):
    """A .dockerignore pattern as a regex over slash-separated paths relative to the context root."""
    out, i = "", 0
    while i < len(pattern):
        if pattern.startswith("**/", i):
            out, i = out + "(?:.*/)?", i + 3
        elif pattern.startswith("**", i):
            out, i = out + ".*", i + 2
        elif pattern[i] == "*":
            out, i = out + "[^/]*", i + 1
        elif pattern[i] == "?":
            out, i = out + "[^/]", i + 1
        else:
            out, i = out + re.escape(pattern[i]), i + 1
    return re.compile(out + r"\Z")


def ignore_rules(path):
    rules = []
    for line in open(path).read().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        exception = line.startswith("!")
        pattern = line[1:] if exception else line
        rules.append((exception, ignore_regex(pattern.strip("/"))))
    return rules


def ignored(rules, path):
    """Docker's rule: the last pattern matching the path or one of its parent folders decides."""
    parts = path.split("/")
    prefixes = ["/".join(parts[:n]) for n in range(1, len(parts) + 1)]
    result = False
    for exception, regex in rules:
        if any(regex.match(p) for p in prefixes):
            result = not exception
    return result


def tracked_files(source_dir):
    try:
        out = subprocess.run(["git", "-C", source_dir, "ls-files"], capture_output=True, text=True, check=True)
        files = out.stdout.splitlines()
        if files:
            return files
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for root, dirs, names in os.walk(source_dir):
        dirs[:] = [d for d in dirs if d != ".git" and d != "node_modules" and not
                   (root == source_dir and d.startswith("build"))]
        files += [os.path.relpath(os.path.join(root, n), source_dir) for n in names]
    return files


# Tracked files the image build never reads; everything else must reach the build context, so a new
# source folder (or a file a new CMakeLists.txt reads) cannot be left out silently.
NOT_NEEDED = re.compile(r"(?:\.ci/|docs/|deploy/|bench/results/|[^/]*\.md\Z|\.[^/]*\Z|scripts/(?!install-deps\.sh\Z))")


def check_dockerignore(source_dir):
    rules = ignore_rules(os.path.join(source_dir, ".dockerignore"))
    files = [f for f in tracked_files(source_dir) if os.path.exists(os.path.join(source_dir, f))]
    missing = [f for f in files if not NOT_NEEDED.match(f) and ignored(rules, f)]
    check("every tracked source file reaches the build context", not missing and len(files) > 0,
          f"{len(missing)} left out, e.g. {missing[:5]}")
    kept = [p for p in [".git/HEAD", "build/roomrender", "build-asan/CMakeCache.txt",
                        "build/test-output/golden/x.png", "clients/web/node_modules/x/package.json",
                        "tests/schema/node_modules/ajv/package.json", "tests/x/__pycache__/y.pyc"]
            if not ignored(rules, p)]
    check(".dockerignore keeps out .git, build trees, node_modules, test outputs", not kept, f"kept {kept}")


# --- compose and Kubernetes -------------------------------------------------------------------------

def data_dir_arg(args):
    args = list(args or [])
    if "--data-dir" in args and args.index("--data-dir") + 1 < len(args):
        return args[args.index("--data-dir") + 1]
    return None


def store_url_ok(value, host):
    return isinstance(value, str) and value.startswith("postgresql://") and f"@{host}:5432/" in value


def check_compose(source_dir, data_dir):
    path = os.path.join(source_dir, "deploy", "compose.yaml")
    doc = yaml.safe_load(open(path))
    services = doc["services"]
    named = set((doc.get("volumes") or {}).keys())
    replicas = {n: s for n, s in services.items() if "build" in s}
    check("compose builds the replicas from the repository's Dockerfile",
          len(replicas) > 1 and all(os.path.isfile(os.path.join(os.path.dirname(path),
                                                                 s["build"] if isinstance(s["build"], str)
                                                                 else s["build"].get("context", "."),
                                                                 "Dockerfile"))
                                    for s in replicas.values()), f"services {list(services)}")
    db = services.get("postgres", {})
    db_mounts = [v.split(":") for v in db.get("volumes", []) if isinstance(v, str)]
    check("compose runs the official postgres image with its data on a named volume",
          str(db.get("image", "")).startswith("postgres:")
          and any(m[0] in named and m[1] == "/var/lib/postgresql/data" for m in db_mounts)
          and "POSTGRES_PASSWORD" in db.get("environment", {}), f"postgres service {db}")
    for name, service in replicas.items():
        env = service.get("environment", {})
        mounts = [v.split(":") for v in service.get("volumes", []) if isinstance(v, str)]
        user = str(service.get("user", RUNTIME_UID)).split(":")[0]
        depends = service.get("depends_on", {})
        check(f"compose {name}: ROOMRENDER_STORE names the postgres service, no volume of its own, "
              f"uid {RUNTIME_UID}",
              store_url_ok(env.get("ROOMRENDER_STORE"), "postgres") and data_dir_arg(service.get("command")) is None
              and not any(m[0] in named for m in mounts) and user in (str(RUNTIME_UID), RUNTIME_USER)
              and "postgres" in depends,
              f"environment {env}, volumes {service.get('volumes')}, user {user}, depends_on {depends}")
    upstream = open(os.path.join(source_dir, "deploy", "nginx", "upstream-compose.conf")).read()
    listed = set(re.findall(r"^\s*server\s+([\w-]+):8080\b", upstream, re.MULTILINE))
    check("upstream-compose.conf lists exactly the replicas", listed == set(replicas),
          f"upstream {sorted(listed)}, replicas {sorted(replicas)}")


def env_named(container, name):
    return next((e for e in container.get("env", []) if e["name"] == name), None)


def check_k8s(source_dir, data_dir):
    docs = [d for d in yaml.safe_load_all(open(os.path.join(source_dir, "deploy", "k8s", "roomrender.yaml"))) if d]
    by_kind = lambda kind: [d for d in docs if d["kind"] == kind]
    sets, deployments, services = by_kind("StatefulSet"), by_kind("Deployment"), by_kind("Service")
    replicas = [d for d in deployments if d["metadata"]["name"] == "roomrender"]
    check("k8s: the replicas are a Deployment named roomrender", len(replicas) == 1, f"{len(replicas)}")
    db_sets = [s for s in sets if any(c["image"].startswith("postgres:")
                                      for c in s["spec"]["template"]["spec"]["containers"])]
    check("k8s: PostgreSQL (official image) is the one StatefulSet", len(sets) == 1 and len(db_sets) == 1,
          f"{[s['metadata']['name'] for s in sets]}")
    secrets = set()
    if db_sets:
        spec = db_sets[0]["spec"]
        claims = {t["metadata"]["name"] for t in spec.get("volumeClaimTemplates", [])}
        db = spec["template"]["spec"]["containers"][0]
        password = (env_named(db, "POSTGRES_PASSWORD") or {}).get("valueFrom", {}).get("secretKeyRef")
        db_service = [s for s in services if s["spec"].get("selector") == spec["selector"]["matchLabels"]]
        secrets.add((password or {}).get("name"))
        check("k8s postgres: data on a claimed volume, password from a Secret, a Service in front",
              any(m["name"] in claims and m["mountPath"] == "/var/lib/postgresql/data"
                  for m in db.get("volumeMounts", [])) and password is not None and len(db_service) == 1,
              f"mounts {db.get('volumeMounts')}, claims {claims}, password {password}")
    if len(replicas) != 1:
        return
    pod = replicas[0]["spec"]["template"]["spec"]
    security = pod.get("securityContext", {})
    check(f"k8s: replica pods run as uid {RUNTIME_UID}, non-root, without volumes",
          security.get("runAsUser") == RUNTIME_UID and security.get("runAsNonRoot") is True
          and not pod.get("volumes"), f"{security}, volumes {pod.get('volumes')}")
    for container in pod["containers"]:
        store = (env_named(container, "ROOMRENDER_STORE") or {}).get("valueFrom", {}).get("secretKeyRef")
        escalation = container.get("securityContext", {}).get("allowPrivilegeEscalation")
        live = container.get("livenessProbe", {}).get("httpGet", {}).get("path")
        check(f"k8s {container['name']}: ROOMRENDER_STORE from the database's Secret, no --data-dir, liveness on /livez, "
              "no privilege escalation",
              store is not None and store.get("name") in secrets and data_dir_arg(container.get("args")) is None and live == "/livez"
              and escalation is False and not container.get("volumeMounts"),
              f"store {store}, args {container.get('args')}, liveness {live}, "
              f"allowPrivilegeEscalation {escalation}")
    labels = replicas[0]["spec"]["selector"]["matchLabels"]
    headless = [s for s in services if s["spec"].get("selector") == labels and s["spec"].get("clusterIP") == "None"]
    upstream = open(os.path.join(source_dir, "deploy", "nginx", "upstream-k8s.conf")).read()
    names = re.findall(r"^\s*server\s+([\w.-]+):8080\b.*\bresolve\b", upstream, re.MULTILINE)
    check("k8s: nginx re-resolves the replicas' headless Service, which lists not-ready pods",
          len(headless) == 1 and headless[0]["spec"].get("publishNotReadyAddresses") is True
          and names == [f"{headless[0]['metadata']['name']}.default.svc.cluster.local"]
          and re.search(r"^\s*zone\s", upstream, re.MULTILINE) is not None,
          f"headless {[s['metadata']['name'] for s in headless]}, upstream servers {names}")


def main():
    source_dir = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
    data_dir = check_dockerfile(source_dir)
    check_dockerignore(source_dir)
    if data_dir:
        check_compose(source_dir, data_dir)
        check_k8s(source_dir, data_dir)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
