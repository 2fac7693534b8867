// How each game looks: cloth, rail and ball colours, and which balls carry numbers or stripes.

export { GAMES } from "../net/protocol.js";

export const GAME_NAMES = {
  nineball: "Nine-ball",
  eightball: "Eight-ball",
  snooker: "Snooker",
  three_cushion: "Three-cushion",
};

/** Cloth and rail colours per game (tournament blue, pub green, snooker green, carom blue). */
export const TABLE_COLOURS = {
  nineball: { cloth: "#1f6fb2", cushion: "#1a62a0", rail: "#4a2614" },
  eightball: { cloth: "#1d7d45", cushion: "#186c3b", rail: "#3b2414" },
  snooker: { cloth: "#11703a", cushion: "#0e6232", rail: "#2e1a0e" },
  three_cushion: { cloth: "#2d5fa8", cushion: "#28559a", rail: "#1f1f24" },
};

/** The colours of the pool balls 1-8 (9-15 are the stripes of 1-7). */
const POOL = ["#f4c20d", "#1c4fb8", "#d42b2b", "#5a2d8c", "#f0700a", "#178a3e", "#7d1e22", "#121212"];

const SNOOKER = {
  yellow: "#f2d31b",
  green: "#17803b",
  brown: "#6e3f1f",
  blue: "#1d52c8",
  pink: "#f39cb8",
  black: "#121212",
};

const CAROM = { white: "#f5f3ea", yellow: "#f3cf10", red: "#c8102e" };

const CUE_WHITE = "#f6f3e8";

/**
 * The look of ball `id` in `game`: {colour, number (text or null), stripe, dots}.
 * dots: small marks on an otherwise plain ball, so that its spin can be seen.
 */
export function ballLook(game, id) {
  if (id === "cue") return { colour: CUE_WHITE, number: null, stripe: false, dots: "#c0282d" };
  if (game === "three_cushion") {
    return { colour: CAROM[id] ?? "#888888", number: null, stripe: false, dots: id === "yellow" ? "#1a1a1a" : null };
  }
  if (game === "snooker") {
    const colour = id.startsWith("red") ? "#b8141b" : (SNOOKER[id] ?? "#888888");
    return { colour, number: null, stripe: false, dots: null };
  }
  const n = Number(id);
  if (!Number.isInteger(n) || n < 1 || n > 15) return { colour: "#888888", number: id, stripe: false, dots: null };
  return { colour: POOL[(n - 1) % 8], number: String(n), stripe: n > 8, dots: null };
}
