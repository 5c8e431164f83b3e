#!/usr/bin/env bash
# Validate the Kubernetes manifests against the Job schema of a recent Kubernetes release (no cluster needed):
# `kubernetes-validate` from PyPI, which carries the official OpenAPI schemas, installed into a virtualenv under
# target/. Also checks that the render Job's completion count equals its --shard denominator and the number of
# parts the merge Job reads. `.ci/run` calls it.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
VENV="$ROOT/target/k8s-venv"
if [ ! -x "$VENV/bin/kubernetes-validate" ]; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install -q kubernetes-validate
fi
VERSION="${K8S_VERSION:-1.31}"
for f in "$ROOT"/deploy/kubernetes/*.yaml; do
    "$VENV/bin/kubernetes-validate" --strict -k "$VERSION" "$f"
done
"$VENV/bin/python" - "$ROOT/deploy/kubernetes" <<'PY'
import re, sys, yaml
d = sys.argv[1]
render = yaml.safe_load(open(f"{d}/render-shards.yaml"))
merge = yaml.safe_load(open(f"{d}/merge.yaml"))
n = render["spec"]["completions"]
assert render["spec"]["completionMode"] == "Indexed", "the render Job must be Indexed"
args = " ".join(render["spec"]["template"]["spec"]["containers"][0]["args"])
assert f'/{n}"' in args, f"--shard denominator differs from completions ({n})"
parts = re.findall(r"part-(\d+)\.prism-film", " ".join(merge["spec"]["template"]["spec"]["containers"][0]["args"]))
assert sorted(map(int, parts)) == list(range(n)), f"the merge Job reads parts {parts}, expected 0..{n - 1}"
print(f"kubernetes manifests: valid Jobs; {n} indexed shards, merge reads all {n} parts")
PY
