#!/usr/bin/env bash
# ubr-petsc set-up and main job.
#   ./run.sh            install what is missing, build, run the paper's Hertz scene on 2 ranks
#   ./run.sh test       install what is missing, build, run the whole test suite
#   ./run.sh test quick the suite without the tests marked #[ignore = "slow"]
#   ./run.sh build      install and build only
# Works as root or as a user with sudo, on Debian 12.
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(petsc-dev libmumps-dev libmumps-headers-dev libopenmpi-dev openmpi-bin libclang-dev pkg-config libopenblas0-serial gmsh fonts-dejavu-core)
# Independent readers for the output tests (.vtu, .pvtu): Debian's meshio and VTK.
TEST_PACKAGES=(python3-meshio python3-vtk9)

install_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "run.sh: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

setup_env() {
  # Open MPI refuses root without these.
  if [ "$(id -u)" -eq 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  fi
  # Keep BLAS single-threaded under MPI.
  export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
  if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
  fi
}

# The Rust that Cargo.toml's rust-version asks for (Debian 12's is too old):
# one line and exit 1 when cargo is missing or older.
check_rust() {
  local need have
  need=$(sed -n 's/^rust-version *= *"\(.*\)"/\1/p' Cargo.toml)
  if ! command -v cargo >/dev/null 2>&1 || ! have=$(rustc --version 2>/dev/null); then
    echo "run.sh: cargo not found: ubr-petsc needs Rust $need or newer; install it with rustup (https://rustup.rs)" >&2
    exit 1
  fi
  have=$(echo "$have" | awk '{print $2}')
  have=${have%%-*}
  if [ "$(printf '%s\n%s\n' "$need" "$have" | sort -V | head -n 1)" != "$need" ]; then
    echo "run.sh: rustc $have is too old: ubr-petsc needs Rust $need or newer; install it with rustup (https://rustup.rs), then 'rustup update'" >&2
    exit 1
  fi
}

build() {
  check_rust
  cargo build --release --locked --quiet || { echo "run.sh: build failed" >&2; exit 1; }
  [ -x target/release/ubr-petsc ] || { echo "run.sh: build failed" >&2; exit 1; }
}

install_packages "${PACKAGES[@]}"
[ "${1:-run}" = test ] && install_packages "${TEST_PACKAGES[@]}"
setup_env
case "${1:-run}" in
  run)
    build
    # Oversubscription only where it is needed: set, Open MPI makes a
    # waiting rank yield its core, which slows the per-iteration exchanges.
    over=()
    [ "$(nproc)" -lt 2 ] && over=(--oversubscribe)
    exec mpirun "${over[@]}" -n 2 target/release/ubr-petsc -options_file options/hertz "${@:2}"
    ;;
  test)
    build
    # The tests run 3 and 4 ranks on 2 cores too.
    export OMPI_MCA_rmaps_base_oversubscribe=1
    # Tests start mpirun themselves; two test binaries at a time on 2 cores.
    # The slow tests (the paper's tables on all five meshes, ...) are
    # #[ignore = "slow"]: included here, left out by `./run.sh test quick`.
    if [ "${2:-}" = quick ]; then
      exec cargo test --release --locked -- --test-threads=2 "${@:3}"
    fi
    exec cargo test --release --locked -- --test-threads=2 --include-ignored "${@:2}"
    ;;
  build)
    build
    ;;
  *)
    echo "usage: ./run.sh [run|test [quick]|build] [extra options]" >&2
    exit 2
    ;;
esac
