// Scenes stored on the server: Save (POST /v1/scenes) with a permalink and an image URL, opening a
// permalink, imports stored by the server (?store=1), and scenes too big for the editor, which are
// rendered by id (big_scene.js keeps their meshes out of the text). In: the editor's request, the
// Api. Out: the editor's text (through the designer, as one step) and the share panel's links.
// Invariant: while a big scene is loaded, `big.id` names a stored scene equal to the editor's scene
// with its meshes put back, whenever `big.key` equals the editor's scene (re-stored on a change).
import { viewOf, permalink, imageUrl } from "./share.js";
import { bigSceneChars, splitMeshes, joinMeshes, isStoredMesh, summarize } from "./big_scene.js";

const $ = (id) => document.getElementById(id);

export class Sharing {
  constructor({ api, editor, designer, onStatus }) {
    this.api = api;
    this.editor = editor;
    this.designer = designer;
    this.onStatus = onStatus;
    this.big = null;      // {id, key, meshes, chars} while a big scene is loaded
    this.saved = null;    // {id, key} of the last Save: the links shown are for it
    $("copy-image-url").addEventListener("click", () => this.copyImageUrl());
  }

  isBig() {
    return this.big !== null;
  }

  // Any other whole new text (New, an example, a small file) ends big-scene mode.
  replaced() {
    this.big = null;
    $("big-summary").hidden = true;
  }

  // The request with the meshes kept out of the editor put back (for downloads and storing).
  fullScene(scene) {
    return this.big ? joinMeshes(scene, this.big.meshes) : scene;
  }

  // The id of the stored scene equal to `scene` (storing it when it changed since).
  async storedId(scene, { signal } = {}) {
    const key = JSON.stringify(scene);
    if (this.big && this.big.key === key) return this.big.id;
    if (this.saved && this.saved.key === key) return this.saved.id;
    const receipt = await this.api.storeScene(this.fullScene(scene), { signal });
    if (this.big) Object.assign(this.big, { id: receipt.id, key });
    return receipt.id;
  }

  // A big scene renders by id; a small one inline as today (the caller's job: null here).
  async render(request, { signal } = {}) {
    if (!this.big) return null;
    const id = await this.storedId(request.scene || {}, { signal });
    return this.api.renderStored(id, viewOf(request), { signal });
  }

  // The element at pixel (x, y) of the request's image (api.pick): by stored id when the scene is
  // big, as it renders; inline otherwise.
  async pick(request, x, y, { signal } = {}) {
    const storedId = this.big ? await this.storedId(request.scene || {}, { signal }) : null;
    return this.api.pick(request, x, y, { storedId, signal });
  }

  // Loads a scene document (text) with a view into the editor: whole when small, else as a big
  // scene with its meshes kept out. `id`: where it is stored already (null: stored on first render).
  load(sceneText, id, view, { step = true } = {}) {
    const scene = JSON.parse(sceneText);
    if (sceneText.length <= bigSceneChars) {
      this.designer.replaceAll(JSON.stringify({ scene, ...view }, null, 2), { render: false, step });
      return;
    }
    const split = splitMeshes(scene);
    this.designer.replaceAll(JSON.stringify({ scene: split.scene, ...view }, null, 2), { render: false, step });
    this.big = { id, key: id ? JSON.stringify(split.scene) : null, meshes: split.meshes, chars: sceneText.length };
    this.showSummary(summarize(split.scene, sceneText.length, split.meshes.size));
  }

  showSummary(text) {
    $("big-summary").textContent = text;
    $("big-summary").hidden = false;
  }

  async openPermalink(id, view) {
    const text = await this.api.storedSceneText(id);
    this.load(text, id, view);
    this.saved = { id, key: JSON.stringify(this.editor.parsed()?.scene) };
  }

  // A file imported and stored by the server. A scene that arrives within `waitMs` fills the editor
  // before the first render; else it renders by id at once, with the camera and options of the
  // server's answer, and fills the editor when it comes (GET /v1/scenes/{id}: the server compresses
  // an interior's megabytes first, which takes it a while).
  async importStored(format, file, { waitMs = 1500 } = {}) {
    const receipt = await this.api.importStored(format, file);
    if (!/^[0-9a-f]{16}$/.test(receipt.id || "")) throw new Error("the import answer names no stored scene");
    const view = { camera: receipt.camera, options: receipt.options };
    const fetched = this.api.storedSceneText(receipt.id).then((text) => ({ text }), (error) => ({ error }));
    const early = await Promise.race([fetched, new Promise((done) => setTimeout(() => done(null), waitMs))]);
    if (early?.text) {
      this.load(early.text, receipt.id, view);
      return receipt;
    }
    this.designer.replaceAll(JSON.stringify(view, null, 2), { render: false });
    this.big = { id: receipt.id, key: JSON.stringify({}), meshes: new Map(), chars: 0, pending: true };
    this.showSummary(`Scene ${receipt.id} is stored on the server and renders from there; fetching it to edit its elements…`);
    fetched.then(({ text, error }) => {
      if (this.big?.id !== receipt.id || !this.big.pending) return;  // another scene came meanwhile
      if (error) {
        this.showSummary(`Scene ${receipt.id} renders from the server, but could not be fetched to edit: ${error.message}`);
        return;
      }
      if (JSON.stringify(this.editor.parsed()?.scene ?? {}) !== this.big.key) return;  // a scene was typed
      this.load(text, receipt.id, viewOf(this.editor.parsed() || view), { step: false });
      if (!this.big) $("big-summary").hidden = true;
    });
    return receipt;
  }

  // Save: stores the editor's scene on the server and shows the links to it.
  async save() {
    const request = this.editor.parsed();
    if (request === null) return this.showError("Not saved on the server: the JSON has an error.");
    this.showError(null);
    this.onStatus("Storing the scene on the server…");
    try {
      const id = await this.storedId(request.scene || {});
      this.saved = { id, key: JSON.stringify(request.scene || {}) };
      this.showLinks(request);
      this.onStatus(`Stored as scene ${id} (also saved in this browser).`);
    } catch (error) {
      const detail = error.errors?.map((e) => (e.pointer ? `${e.pointer}: ${e.detail}` : e.detail)).join("; ") || error.message;
      this.showError(`The server did not store the scene (${error.status ? `HTTP ${error.status}` : "no answer"}): ${detail}`);
    }
    return this.saved?.id ?? null;
  }

  // The links of the saved scene for the request's current camera and options; when the scene
  // changed since it was saved, they say so (Save again makes new ones).
  showLinks(request = this.editor.parsed()) {
    if (!this.saved || !request) return;
    const view = viewOf(request);
    const origin = location.origin;
    const link = permalink(origin, this.saved.id, view);
    const image = imageUrl(origin, this.saved.id, view);
    $("permalink").href = link;
    $("permalink").textContent = link;
    $("image-url").value = image.url;
    const changed = JSON.stringify(request.scene || {}) !== this.saved.key;
    $("share-note").textContent = changed ? "The scene changed since it was saved: these links show it as saved; Save again for new ones."
      : image.missing.length ? `The image URL leaves out ${image.missing.join(", ")} (no query parameter for them).` : "";
    $("share").hidden = false;
    $("share-links").hidden = false;
  }

  async copyImageUrl() {
    if (!this.saved && !(await this.save())) return;
    this.showLinks();
    try {
      await navigator.clipboard.writeText($("image-url").value);
      this.onStatus("Copied the image URL.");
    } catch {
      $("image-url").select();
      this.onStatus("The browser did not let the page copy: the image URL is selected, press Ctrl+C.");
    }
  }

  // A visible message in the share panel (null hides it).
  showError(text) {
    $("share-message").textContent = text || "";
    $("share-message").hidden = !text;
    if (text) {
      $("share").hidden = false;
      this.onStatus(text);
    }
  }

  // The schema checker, minus what it says about the stand-ins for meshes kept out of the editor.
  filterChecker(check) {
    return (request) => check(request).filter((d) => {
      const m = /^\/scene\/solids\/(\d+)/.exec(d.pointer || "");
      return !(m && isStoredMesh(request?.scene?.solids?.[Number(m[1])]));
    });
  }

  // What the browser keeps: the editor's text, or for a big scene (too big for the browser's
  // storage, and its text has the meshes kept out) a link to its stored copy; null: nothing yet.
  autosaveText() {
    if (!this.big) return this.editor.text();
    if (!this.big.id) return null;
    return JSON.stringify({ stored_scene: this.big.id, view: viewOf(this.editor.parsed() || {}) });
  }
}

// The browser's copy of a big scene is a link to it (autosaveText above), as a search part.
export function storedSceneLink(saved) {
  if (!saved || !saved.startsWith('{"stored_scene"')) return null;
  try {
    const { stored_scene: id, view } = JSON.parse(saved);
    return `?scene=${encodeURIComponent(id)}&view=${encodeURIComponent(JSON.stringify(view || {}))}`;
  } catch {
    return null;
  }
}
