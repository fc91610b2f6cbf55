// Selecting and moving on the rendered image with the Select tool. In: a pointer press on the image
// (page pixels), the request, and pick(request, x, y) (the service's picking: the element the id
// buffer shows at an image pixel, and the world point there). Out: a click selects that element in
// the designer; a drag that starts on a solid moves it as a plan drag does (the designer's drag
// state, 5 cm grid, reduced-size renders as it goes, one step on release): the grabbed point follows
// the pointer on the horizontal plane through it. A drag that starts elsewhere stays a camera drag.
import { pixelRay, rayAtHeight } from "./camera.js";
import { at, clone } from "./designer_util.js";

const clickPx = 3;  // a press that moves less than this is a click

// The image pixel (fractional, full-size image) under page point (x, y): {u, v, w, h, inside}.
export function pageToView(img, options, x, y) {
  const r = img.getBoundingClientRect();
  const w = options?.width ?? 640;
  const h = options?.height ?? 480;
  const u = ((x - r.left) / (r.width || 1)) * w;
  const v = ((y - r.top) / (r.height || 1)) * h;
  return { u, v, w, h, inside: r.width > 0 && u >= 0 && v >= 0 && u < w && v < h };
}

// Returns viewer.js's grab hook: for a press on `img` with the Select tool, an object the viewer asks
// mode() ("pending" until the pick answers, then "move" or "orbit") and gives move(e) and end(e).
// `enabled()`: whether the server picks at all (an older one has no POST /v1/pick: drags orbit).
export function viewGrabber({ designer, img, pick, onError, enabled = () => true }) {
  return (e) => {
    if (designer.tool !== "select" || e.target !== img || !enabled()) return null;
    const request = designer.request();
    const start = request && pageToView(img, request.options, e.clientX, e.clientY);
    if (!start?.inside) return null;
    let picked;  // undefined while the pick is on its way; then the answer, or null when it failed
    let last = e;
    let moved = false;
    let ended = false;
    let dragging = false;  // the designer's drag state was set up
    const isSolid = () => /^\/scene\/solids\/\d+$/.test(picked?.pointer || "") && Array.isArray(picked.point);

    // The plan point under page point (x, y) on the grabbed point's height.
    const floorAt = (x, y) => {
      const p = pageToView(img, request.options, x, y);
      return rayAtHeight(pixelRay(request.camera, p.w, p.h, p.u, p.v), picked.point[1]);
    };
    const follow = (ev) => {
      const p = floorAt(ev.clientX, ev.clientY);
      if (!p) return;
      if (!dragging) {
        const element = at(request, picked.pointer);
        designer.drag = { pointer: picked.pointer, from: [picked.point[0], picked.point[2]], original: clone(element),
          moved: false, scene: null };
        dragging = true;
      }
      designer.pointerMove(p);
    };
    const finish = () => {
      if (dragging) designer.pointerUp();
      else if (!moved && picked !== null) designer.select(picked.pointer);
    };

    const answer = pick(request, Math.floor(start.u), Math.floor(start.v)).then((a) => a, (error) => {
      onError(error);
      return null;
    });
    answer.then((a) => {
      picked = a;
      if (isSolid()) designer.select(picked.pointer);
      if (!ended) {
        if (moved && isSolid()) follow(last);
        return;
      }
      if (moved && isSolid()) follow(last);  // the whole drag happened before the answer came
      finish();
    });
    return {
      mode: () => (picked === undefined ? "pending" : isSolid() ? "move" : "orbit"),
      move(ev) {
        last = ev;
        if (Math.hypot(ev.clientX - e.clientX, ev.clientY - e.clientY) >= clickPx) moved = true;
        if (moved && picked !== undefined && isSolid()) follow(ev);
      },
      end(ev) {
        last = ev;
        ended = true;
        if (picked !== undefined) finish();
      },
      done: answer,  // resolves once the pick has answered (the page counts it as loading)
    };
  };
}
