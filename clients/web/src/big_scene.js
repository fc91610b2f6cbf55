// Scenes too big for the editor (an imported interior: megabytes of mesh vertices). The editor gets
// the scene with each mesh's large arrays replaced by a short `stored_mesh` note, so walls, lights,
// non-mesh solids and a mesh's placement stay editable; the arrays stay here, keyed by the note's
// token, and are put back before the scene is stored again. Pure functions; no DOM.

export const bigSceneChars = 1_000_000;   // a scene text longer than this is not pasted into the editor
const keptChars = 200;                     // mesh members whose JSON is longer are kept out of the editor

// {scene, meshes}: `scene` with its mesh solids' large members kept out (a new object), and
// `meshes`, a Map from token to those members.
export function splitMeshes(scene) {
  const meshes = new Map();
  const solids = (scene.solids || []).map((s, i) => {
    if (!s || s.type !== "mesh") return s;
    const light = {};
    const kept = {};
    for (const [k, v] of Object.entries(s)) {
      if (JSON.stringify(v).length > keptChars) kept[k] = v;
      else light[k] = v;
    }
    if (!Object.keys(kept).length) return s;
    const token = `m${i}`;
    meshes.set(token, kept);
    const counts = Object.entries(kept).map(([k, v]) => `${Array.isArray(v) ? v.length : 1} ${k}`).join(", ");
    // The corners of the vertices' bounding box stand in for them, so the plan still draws the mesh.
    const box = kept.vertices ? { vertices: boxCorners(kept.vertices) } : {};
    return { ...light, ...box, stored_mesh: `${token}: ${counts} (kept out of the editor; vertices here: its bounding box)` };
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
  const solids = scene.solids.map((s) => {
    const kept = s && meshes.get(tokenOf(s.stored_mesh));
    if (!kept) return s;
    const { stored_mesh: _note, ...rest } = s;
    return { ...rest, ...kept };
  });
  return { ...scene, solids };
}

// Is the solid at this index a stand-in for a mesh kept out of the editor?
export function isStoredMesh(solid) {
  return Boolean(solid && typeof solid.stored_mesh === "string");
}

// One line about a big scene for above the editor.
export function summarize(scene, chars, meshCount) {
  const n = (k) => (Array.isArray(scene[k]) ? scene[k].length : 0);
  const mb = (chars / 1e6).toFixed(2);
  return `${mb} MB scene: ${n("walls")} walls, ${n("solids")} solids (${meshCount} meshes kept out of the editor), ` +
    `${n("lights")} lights. The rest is edited here and in the plan.`;
}
