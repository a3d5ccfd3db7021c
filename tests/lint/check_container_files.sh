#!/usr/bin/env bash
# Lints docker/: yamllint on the YAML (compose, Kubernetes), and basic checks of the Dockerfiles
# (Debian 12 base, no recommends, apt lists removed, the build packages of scripts/setup) and of
# the nginx template (WebSocket upgrade, affinity). Usage: check_container_files.sh SOURCE_DIR
set -euo pipefail

root="$1"
docker="$root/docker"
problems=0
problem() {
  echo "check_container_files: $*" >&2
  problems=$((problems + 1))
}

if command -v yamllint >/dev/null; then
  yamllint -s -c "$docker/.yamllint" "$docker"/*.yaml || problem "yamllint found problems"
else
  problem "yamllint is not installed (scripts/setup installs it)"
fi

for dockerfile in "$docker"/Dockerfile*; do
  name="${dockerfile#"$root"/}"
  [[ "$(grep -m1 '^FROM' "$dockerfile")" == "FROM debian:12"* ]] || problem "$name: not FROM debian:12"
  grep -q -- '--no-install-recommends' "$dockerfile" || problem "$name: apt-get without --no-install-recommends"
  grep -q 'rm -rf /var/lib/apt/lists' "$dockerfile" || problem "$name: apt lists left in the image"
  if grep -qE '^\s*ADD ' "$dockerfile"; then problem "$name: ADD (use COPY)"; fi
  grep -q '^CMD \[' "$dockerfile" || problem "$name: CMD not in exec form"
done

# The daemon's image installs what scripts/setup installs for a build.
mapfile -t packages < <(sed -n '/^packages=(/,/^)/p' "$root/scripts/setup" | tr ' ' '\n' \
  | grep -vE '^(packages=\(|\)|)$')
((${#packages[@]} > 5)) || problem "cannot read the package list of scripts/setup"
for package in "${packages[@]}"; do
  grep -qw -- "$package" "$docker/Dockerfile" || problem "docker/Dockerfile lacks $package (scripts/setup has it)"
done

for needed in 'proxy_set_header Upgrade $http_upgrade' 'proxy_set_header Connection $connection_upgrade' \
  'proxy_http_version 1.1' 'hash $hdof_affinity consistent' 'server hdof-1:8080' 'listen 8080;'; do
  grep -qF -- "$needed" "$docker/nginx.conf" || problem "docker/nginx.conf lacks '$needed'"
done
for needed in 'kind: Deployment' 'kind: Service' 'kind: HorizontalPodAutoscaler' 'path: /healthz' \
  'readinessProbe' 'livenessProbe' 'name: hdof_sessions'; do
  grep -qF -- "$needed" "$docker/k8s.yaml" || problem "docker/k8s.yaml lacks '$needed'"
done

((problems == 0)) || exit 1
echo "check_container_files: docker/ is clean"
