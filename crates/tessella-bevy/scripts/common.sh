# Sourced by the frame-time scripts, in the crate's folder once `profile` is set: the view
# example of that profile (refused when it is not built), the CLI, the samples, a temporary
# folder removed on exit, and `median`.
view=target/$profile/examples/view
cli=${TESSELLA_BIN:-../../target/release/tessella}
samples=../../samples
[ -x "$view" ] || { echo "build it first: cargo build --$profile --example view" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The median of the numbers on standard input, one a line.
median() { sort -g | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
