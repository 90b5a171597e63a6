// Side-by-side panels laid out as tessella-view's render_compare lays them out.

/** Separator between panels, pixels (tessella-view's font::GAP). */
export const GAP = 2;

/**
 * Widths of `n` panels filling `total` pixels with GAP-pixel separators, the first ones one
 * pixel wider when it does not divide evenly (tessella-view's `panel_widths`); null when a
 * panel would be narrower than one pixel.
 */
export function panelWidths(total, n) {
  const room = total - (n - 1) * GAP;
  const base = Math.floor(room / n);
  if (!(n >= 1) || base <= 0) return null;
  return Array.from({ length: n }, (_, i) => base + (i < room % n ? 1 : 0));
}
