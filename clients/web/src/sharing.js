// Scenes stored on the server: Save (POST /v1/scenes) with a permalink and an image URL, opening a
// permalink, imports stored by the server (?store=1), and scenes too big for the editor, which are
// rendered by id (big_scene.js keeps their meshes out of the text). In: the editor's request, the
// Api. Out: the editor's text (through the designer, as one step) and the share panel's links.
// Invariant: while a big scene is loaded, `big.id` names a stored scene equal to the editor's scene
// with its meshes put back, whenever `big.key` equals the editor's scene (re-stored on a change).
// Camera moves render a stored copy by id (the server keeps it prepared): the saved or imported scene
// when the editor's scene is still that, else the page's one working copy, stored when a camera move
// finds the scene changed; storing a new working copy deletes the one before it when this page
// created it. Edits render inline, so a session of edits leaves one working copy in the store.
import { viewOf, permalink, imageUrl } from "./share.js";
import { plainWords } from "./api.js";
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
    this.working = null;  // {id, key, created} of the working copy camera moves render
    this.storing = null;  // {key, promise} of the working copy being stored
    this.noWorking = false;  // set once the server would not store one
    this.keys = new WeakMap();  // scene object -> its JSON (a parsed scene is read-only)
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

  keyOf(scene) {
    let key = this.keys.get(scene);
    if (key === undefined) {
      key = JSON.stringify(scene);
      this.keys.set(scene, key);
    }
    return key;
  }

  // The id of the stored scene equal to `scene` (storing it when it changed since).
  async storedId(scene, { signal } = {}) {
    const key = this.keyOf(scene);
    if (this.big && this.big.key === key) return this.big.id;
    if (this.saved && this.saved.key === key) return this.saved.id;
    const receipt = await this.api.storeScene(this.fullScene(scene), { signal });
    if (this.big) Object.assign(this.big, { id: receipt.id, key });
    return receipt.id;
  }

  // A big scene renders by id; a small one by id when a stored copy holds it (`store`: a camera move,
  // which stores the working copy when none does), else inline (the caller's job: null here).
  async render(request, { signal, store = false } = {}) {
    const scene = request.scene || {};
    const id = this.big ? await this.storedId(scene, { signal })
      : this.copyOf(scene) ?? (store ? await this.storeWorking(scene) : null);
    return id ? this.api.renderStored(id, viewOf(request), { signal }) : null;
  }

  // The id of a stored scene that is `scene` (saved, imported or the working copy), or null.
  copyOf(scene) {
    if (!this.saved && !this.working) return null;
    const key = this.keyOf(scene);
    if (this.saved?.key === key) return this.saved.id;
    if (this.working?.key === key) return this.working.id;
    return null;
  }

  // Stores `scene` as the working copy (null when the server will not: no store, a token needed, the
  // store full; camera moves then render inline). The one before goes when this page created it.
  async storeWorking(scene) {
    if (this.noWorking || !this.api.has("/v1/scenes") || !this.api.has("/v1/scenes/{id}/render")) return null;
    const key = this.keyOf(scene);
    if (this.storing?.key !== key) {
      const promise = this.api.storeScene(key).then((receipt) => {
        const old = this.working;
        this.working = { id: receipt.id, key, created: receipt.created };
        if (old?.created && old.id !== receipt.id && old.id !== this.saved?.id) this.api.deleteScene(old.id).catch(() => {});
        return receipt.id;
      }, () => {
        this.noWorking = true;
        return null;
      }).finally(() => {
        if (this.storing?.promise === promise) this.storing = null;
      });
      this.storing = { key, promise };
    }
    return this.storing.promise;
  }

  // The element at pixel (x, y) of the request's image (api.pick): by stored id when the scene is
  // big, as it renders; inline otherwise.
  async pick(request, x, y, { signal } = {}) {
    const storedId = this.big ? await this.storedId(request.scene || {}, { signal }) : this.copyOf(request.scene || {});
    return this.api.pick(request, x, y, { storedId, signal });
  }

  // Loads a scene document (text) with a view into the editor: whole when small, else as a big
  // scene with its meshes kept out. `id`: where it is stored already (null: stored on first render).
  load(sceneText, id, view, { step = true } = {}) {
    const scene = JSON.parse(sceneText);
    if (sceneText.length <= bigSceneChars) {
      this.designer.replaceAll(JSON.stringify({ scene, ...view }, null, 2), { render: false, step });
      if (id) this.working = { id, key: JSON.stringify(scene), created: false };
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
    if (this.working?.id === id) this.working.created = false;  // saved: it stays
  }

  // A file imported and stored by the server. A scene that arrives within `waitMs` fills the editor
  // before the first render; else it renders by id at once, with the camera and options of the
  // server's answer, and fills the editor when it comes (GET /v1/scenes/{id}: the server compresses
  // an interior's megabytes first, which takes it a while).
  // `models`: a home's furniture drawn with its models (else boxes); `scale`: metres per file unit;
  // `look`: options the view starts with where the server's answer sets none.
  async importStored(format, file, { waitMs = 1500, models = true, scale = null, look = {} } = {}) {
    const receipt = await this.api.importStored(format, file, { models: models && format === "sh3d", scale });
    if (!/^[0-9a-f]{16}$/.test(receipt.id || "")) throw new Error("the import answer names no stored scene");
    const view = { camera: receipt.camera, options: { ...look, ...receipt.options } };
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
      this.load(text, receipt.id, viewOf(this.designer.request() || view), { step: false });
      if (!this.big) $("big-summary").hidden = true;
    });
    return receipt;
  }

  // Save: stores the editor's scene on the server and shows the links to it.
  async save() {
    const request = this.designer.request();
    if (request === null) return this.showError("Not saved on the server: the JSON has an error.");
    this.showError(null);
    this.onStatus("Storing the scene on the server…");
    try {
      const id = await this.storedId(request.scene || {});
      this.saved = { id, key: JSON.stringify(request.scene || {}) };
      if (this.working?.id === id) this.working.created = false;  // saved: it stays
      this.showLinks(request);
      this.onStatus(`Stored as scene ${id} (also saved in this browser).`);
    } catch (error) {
      const detail = plainWords(error) ?? (error.errors?.map((e) => (e.pointer ? `${e.pointer}: ${e.detail}` : e.detail)).join("; ") || error.message);
      this.showError(`The server did not store the scene (${error.status ? `HTTP ${error.status}` : "no answer"}): ${detail}`);
    }
    return this.saved?.id ?? null;
  }

  // The links of the saved scene for the request's current camera and options; when the scene
  // changed since it was saved, they say so (Save again makes new ones).
  showLinks(request = this.designer.request()) {
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

  // A visible message in the share panel (null hides it). `transient`: about the server at that
  // moment (busy, store full on an import); the next image drawn takes it away.
  showError(text, { transient = false } = {}) {
    $("share-message").textContent = text || "";
    $("share-message").hidden = !text;
    this.transientMessage = Boolean(text) && transient;
    if (text) {
      $("share").hidden = false;
      this.onStatus(text);
    }
  }

  // An image was drawn: a transient message no longer holds.
  rendered() {
    if (this.transientMessage) this.showError(null);
  }

  // The scene `id` was deleted from the server: no copy of this page names it any longer (the next
  // camera move or Save stores the scene again), and the store may have room for a working copy.
  forget(id) {
    if (this.saved?.id === id) {
      this.saved = null;
      $("share-links").hidden = true;
    }
    if (this.working?.id === id) this.working = null;
    if (this.big?.id === id && !this.big.pending) Object.assign(this.big, { id: null, key: null });
    this.mayStoreAgain();
  }

  // The server may store a working copy now (a token was entered, or a scene deleted).
  mayStoreAgain() {
    this.noWorking = false;
  }

  // Is `id` a stored copy of the editor's scene (saved, imported, opened, or its working copy)?
  holds(id) {
    if (this.big) return this.big.id === id;
    const scene = this.editor.parsed()?.scene;
    return Boolean(scene) && this.copyOf(scene) === id;
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
    return JSON.stringify({ stored_scene: this.big.id, view: viewOf(this.designer.request() || {}) });
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
