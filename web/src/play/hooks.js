// What the browser tests read of the play page, in one place (window.billiards):
// animations: per animation, its frame intervals and the main thread's time per frame (ms), the
//   resolution scale reached and whether the renderer was taken for a software one;
// shown / version: how many table states have been shown, and the version of the last;
// balls(): where each ball is drawn, in table coordinates; screenOf(p): where on the page a
//   table point is drawn; camera(): the view last drawn ("aim" or "top"); drawn(): whether
//   every change asked for has been drawn; sound(): the sounds' state and counts;
// aim(): the aim as the controls hold it and the first ball on its line, with whether the
//   server lists it as a legal first contact; placement(): the cue ball placed in hand, or null;
//   region(): the ball-in-hand region drawn, or null; botAims(): how many bot shots were shown
//   lined up before they were played; sending: whether an intent awaits the server's answer;
// table(): the geometry the table is drawn from (the server's, at the table's size);
// practice(): on a practice table, the position being set up (null when none) and the last
//   shared position's link; render(): draw the page again from its state, as any message
//   that arrives does.
// The page fills them in as it builds what they read; nothing else writes here.

export const hooks = { animations: [], shown: 0, version: undefined };
window.billiards = hooks;

/** Count one table state shown (a view, or an outcome at the end of its animation). */
export function countShown(version) {
  hooks.shown += 1;
  hooks.version = version;
}
