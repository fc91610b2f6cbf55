// The plan's levels, as Sweet Home 3D's tabs: one tab per storey of scene.levels, lowest first, and
// "All". Choosing a storey draws it and the storeys below it in the image (options.levels) and shows
// only its elements (and those on no level) in the plan, where new walls, furniture and lights go on
// it; "All" draws the viewable storeys, as a request without options.levels does, and shows every
// element in the plan.

// The scene's levels with an id, lowest first (by elevation, then in the scene's order).
export function sceneLevels(scene) {
  const levels = (Array.isArray(scene?.levels) ? scene.levels : []).filter((l) => l && typeof l.id === "string" && l.id);
  return levels.map((l, i) => ({ l, i }))
    .sort((a, b) => (a.l.elevation ?? 0) - (b.l.elevation ?? 0) || a.i - b.i)
    .map(({ l }) => l);
}

// options.levels for the tab `id`: that storey and the storeys before it in sceneLevels' order (null:
// the viewable ones).
export function levelsToDraw(scene, id) {
  const levels = sceneLevels(scene);
  const k = levels.findIndex((l) => l.id === id);
  if (k < 0) return levels.filter((l) => l.viewable !== false).map((l) => l.id);
  return levels.slice(0, k + 1).map((l) => l.id);
}

// A tab's label: the level's id and its floor's height.
export const levelLabel = (level) => `${level.id} · ${Number((level.elevation ?? 0).toFixed(2))} m`;

// The tab a request shows: the highest storey its options.levels draws, or null (All) without them.
export function levelShown(request) {
  const drawn = request?.options?.levels;
  if (!Array.isArray(drawn) || !drawn.length) return null;
  const levels = sceneLevels(request.scene).filter((l) => drawn.includes(l.id));
  if (!levels.length) return null;
  const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);
  return same(levels.map((l) => l.id), levelsToDraw(request.scene, null)) ? null : levels[levels.length - 1].id;
}

// Whether the plan shows element `el` when the tab `id` is chosen (null: All).
export const onLevel = (el, id) => id === null || !el || typeof el.level !== "string" || el.level === id;
