// Scenes too big for the editor (an imported interior: megabytes of mesh vertices). The editor gets
// the scene with each mesh's (and each piece part's) large arrays replaced by a short `stored_mesh`
// note, so walls, lights, other solids and the placements stay editable; the arrays stay here, keyed by the note's
// token, and are put back before the scene is stored again. Pure functions; no DOM.

export const bigSceneChars = 1_000_000;   // a scene text longer than this is not pasted into the editor
const keptChars = 200;                     // mesh members whose JSON is longer are kept out of the editor

// {scene, meshes}: `scene` with the large members of its mesh solids and of its pieces' parts kept
// out (a new object), and `meshes`, a Map from token to those members.
export function splitMeshes(scene) {
  const meshes = new Map();
  // The holder of a mesh with its large members replaced by a note (the holder itself when none is).
  const split = (holder, token) => {
    const light = {};
    const kept = {};
    for (const [k, v] of Object.entries(holder)) {
      if (JSON.stringify(v).length > keptChars && k !== "parts") kept[k] = v;
      else light[k] = v;
    }
    if (!Object.keys(kept).length) return holder;
    meshes.set(token, kept);
    const counts = Object.entries(kept).map(([k, v]) => `${Array.isArray(v) ? v.length : 1} ${k}`).join(", ");
    // The corners of the vertices' bounding box stand in for them, so the plan still draws the mesh.
    const box = kept.vertices ? { vertices: boxCorners(kept.vertices) } : {};
    return { ...light, ...box, stored_mesh: `${token}: ${counts} (kept out of the editor; vertices here: its bounding box)` };
  };
  const solids = (scene.solids || []).map((s, i) => {
    if (s && s.type === "piece" && Array.isArray(s.parts)) {
      const parts = s.parts.map((part, k) => (part && typeof part === "object" ? split(part, `m${i}.${k}`) : part));
      return parts.some((part, k) => part !== s.parts[k]) ? { ...s, parts } : s;
    }
    return s && s.type === "mesh" ? split(s, `m${i}`) : s;
  });
  return { scene: scene.solids ? { ...scene, solids } : { ...scene }, meshes };
}

function boxCorners(vertices) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (const v of vertices) {
    for (let k = 0; k < 3; k++) {
      if (v[k] < lo[k]) lo[k] = v[k];
      if (v[k] > hi[k]) hi[k] = v[k];
    }
  }
  const corners = [];
  for (const x of [lo[0], hi[0]]) for (const y of [lo[1], hi[1]]) for (const z of [lo[2], hi[2]]) corners.push([x, y, z]);
  return corners;
}

const tokenOf = (note) => (typeof note === "string" ? note.split(":")[0] : null);

// The whole scene again: each `stored_mesh` note replaced by the members it stands for. A note whose
// token is unknown (typed by hand) is left as it is, so the server names it.
export function joinMeshes(scene, meshes) {
  if (!Array.isArray(scene.solids)) return scene;
  const join = (holder) => {
    const kept = holder && meshes.get(tokenOf(holder.stored_mesh));
    if (!kept) return holder;
    const { stored_mesh: _note, ...rest } = holder;
    return { ...rest, ...kept };
  };
  const solids = scene.solids.map((s) => (s && Array.isArray(s.parts) ? { ...s, parts: s.parts.map(join) } : join(s)));
  return { ...scene, solids };
}

// Is the solid (or one of its parts) a stand-in for a mesh kept out of the editor?
export function isStoredMesh(solid) {
  return Boolean(solid && (typeof solid.stored_mesh === "string" ||
    (Array.isArray(solid.parts) && solid.parts.some((part) => typeof part?.stored_mesh === "string"))));
}

// One line about a big scene for above the editor.
export function summarize(scene, chars, meshCount) {
  const n = (k) => (Array.isArray(scene[k]) ? scene[k].length : 0);
  const mb = (chars / 1e6).toFixed(2);
  return `${mb} MB scene: ${n("walls")} walls, ${n("solids")} solids (${meshCount} meshes kept out of the editor), ` +
    `${n("lights")} lights. The rest is edited here and in the plan.`;
}
