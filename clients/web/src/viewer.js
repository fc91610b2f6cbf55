// Gestures on the rendered image, turned into camera moves (camera.js does the geometry). In: pointer,
// wheel and key events on the image area. Out: calls of onMove(kind, ...args) with kind "orbit"
// (degrees of azimuth, elevation), "pan" (pixels dx, dy, image height) or "zoom" (distance factor),
// at most once per animation frame: a drag produces many events, and each move asks for a render.
// onGrab(e) may take a left press over (view_select.js): it answers mode() "pending" (moves are held),
// "move" (it gets move(e) and the camera stays) or "orbit" (the held moves turn the camera), and end(e).
import { wheelFactor } from "./camera.js";

const degreesPerPixel = 0.4;
const keyOrbitDeg = 5;
const keyPanPx = 24;
const keyZoom = 0.9;

export function attachViewer(area, { onMove, onReset, onToggleCompare, onDragEnd = () => {}, onGrab = () => null }) {
  let drag = null;  // {x, y, mode, height}
  let pending = { orbit: [0, 0], pan: [0, 0], height: 1, zoom: 1 };
  let frame = 0;

  const flush = () => {
    frame = 0;
    const p = pending;
    pending = { orbit: [0, 0], pan: [0, 0], height: p.height, zoom: 1 };
    if (p.orbit[0] || p.orbit[1]) onMove("orbit", p.orbit[0], p.orbit[1]);
    if (p.pan[0] || p.pan[1]) onMove("pan", p.pan[0], p.pan[1], p.height);
    if (p.zoom !== 1) onMove("zoom", p.zoom);
  };
  const schedule = () => {
    if (!frame) frame = requestAnimationFrame(flush);
  };

  // The image's on-screen height: pan distances are in screen pixels of the picture.
  const imageHeight = (target) => {
    const img = target.closest("figure")?.querySelector("img, canvas") || area.querySelector("img");
    return img ? img.getBoundingClientRect().height || 1 : 1;
  };

  area.addEventListener("pointerdown", (e) => {
    if (!e.target.closest("figure")) return;
    const mode = e.button === 0 && !e.shiftKey ? "orbit" : "pan";
    const grab = mode === "orbit" ? onGrab(e) : null;
    drag = { x: e.clientX, y: e.clientY, mode, height: imageHeight(e.target), id: e.pointerId, grab, held: [0, 0] };
    area.setPointerCapture(e.pointerId);
    area.classList.add("dragging");
    area.focus({ preventScroll: true });
    e.preventDefault();
  });
  area.addEventListener("pointermove", (e) => {
    if (!drag || e.pointerId !== drag.id) return;
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    const grabbed = drag.grab ? drag.grab.mode() : "orbit";
    if (drag.grab) drag.grab.move(e);
    if (grabbed === "move") return;
    if (grabbed === "pending") {
      drag.held[0] += dx;
      drag.held[1] += dy;
      return;
    }
    if (drag.held[0] || drag.held[1]) {
      pending.orbit[0] += drag.held[0] * degreesPerPixel;
      pending.orbit[1] += drag.held[1] * degreesPerPixel;
      drag.held = [0, 0];
    }
    if (drag.mode === "orbit") {
      pending.orbit[0] += dx * degreesPerPixel;
      pending.orbit[1] += dy * degreesPerPixel;
    } else {
      pending.pan[0] += dx;
      pending.pan[1] += dy;
      pending.height = drag.height;
    }
    schedule();
  });
  const end = (e) => {
    if (!drag || e.pointerId !== drag.id) return;
    if (drag.grab) drag.grab.end(e);
    drag = null;
    if (frame) {
      cancelAnimationFrame(frame);
      flush();  // the last moves, while still "dragging", so they too come back small
    }
    area.classList.remove("dragging");
    onDragEnd();
  };
  area.addEventListener("pointerup", end);
  area.addEventListener("pointercancel", end);
  area.addEventListener("contextmenu", (e) => e.preventDefault());  // right-drag pans
  area.addEventListener("wheel", (e) => {
    if (!e.target.closest("figure")) return;
    e.preventDefault();
    const lines = e.deltaMode === 1 ? 33 : e.deltaMode === 2 ? 400 : 1;  // lines or pages -> pixels
    pending.zoom *= wheelFactor(e.deltaY * lines);
    schedule();
  }, { passive: false });

  area.addEventListener("keydown", (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const arrows = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };
    if (arrows[e.key]) {
      const [x, y] = arrows[e.key];
      if (e.shiftKey) onMove("pan", x * keyPanPx, y * keyPanPx, imageHeight(area));
      else onMove("orbit", x * keyOrbitDeg, y * keyOrbitDeg);
    } else if (e.key === "+" || e.key === "=" || e.key === "PageUp") {
      onMove("zoom", keyZoom);
    } else if (e.key === "-" || e.key === "_" || e.key === "PageDown") {
      onMove("zoom", 1 / keyZoom);
    } else if (e.key === "0" || e.key === "Home") {
      onReset();
    } else if (e.key === "c" || e.key === "C") {
      onToggleCompare();
    } else {
      return;
    }
    e.preventDefault();
  });
}
