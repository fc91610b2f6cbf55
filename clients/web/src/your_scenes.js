// "Your scenes": the scenes stored on the server (GET /v1/scenes, newest first; with tokens the
// token owner's, on an open server only with --allow-listing), each with its id, size and date, a
// button that opens it as the working scene and one that deletes it after a confirmation in its row.
// In: the Api, `onOpen(id)` (main.js loads it), `onDeleted(id)` (sharing forgets its copies), and
// `isHere(id)` (the scene is the one open in the page), `onToken()` (a token was entered). The access token a server with
// --api-token-file asks for is typed here, kept for this tab only (sessionStorage) and sent by the Api
// with every write.
const $ = (id) => document.getElementById(id);
const tokenKey = "roomrender.token";

export function formatBytes(n) {
  if (!Number.isFinite(n)) return "";
  if (n < 1024) return `${n} B`;
  if (n < 1024 * 1024) return `${(n / 1024).toFixed(1)} KB`;
  return `${(n / (1024 * 1024)).toFixed(1)} MB`;
}

// What a refusal of the list means, in plain words with what to do.
export function listRefusal(error) {
  if (error?.status === 401) {
    return "This server keeps scenes per access token (it runs with --api-token-file): enter yours above and press Show my scenes.";
  }
  if (error?.status === 403) {
    return "This server does not list stored scenes: it has no access tokens and was not started with --allow-listing 1. " +
      "Your saved scenes are still there, reachable by their links.";
  }
  if (error?.status === 404 || error?.status === 405) return "This server cannot list stored scenes (it has no GET /v1/scenes).";
  return null;
}

export class YourScenes {
  constructor({ api, onOpen, onDeleted, isHere, onToken = () => {} }) {
    this.api = api;
    this.onToken = onToken;
    this.onOpen = onOpen;
    this.onDeleted = onDeleted;
    this.isHere = isHere;
    this.next = null;
    this.loading = null;
    let token = null;
    try {
      token = sessionStorage.getItem(tokenKey);
    } catch {
      // storage refused (a private window): the token lasts as long as the page
    }
    if (token) {
      api.token = token;
      $("scenes-token").value = token;
      $("scenes-token-row").hidden = false;
    }
    $("your-scenes").addEventListener("toggle", () => {
      if ($("your-scenes").open) this.refresh();
    });
    $("scenes-refresh").addEventListener("click", () => this.refresh());
    $("scenes-more").addEventListener("click", () => this.refresh({ more: true }));
    $("scenes-token-form").addEventListener("submit", (e) => {
      e.preventDefault();
      this.setToken($("scenes-token").value.trim());
      this.onToken();
      this.refresh();
    });
  }

  setToken(token) {
    this.api.token = token || null;
    try {
      if (token) sessionStorage.setItem(tokenKey, token);
      else sessionStorage.removeItem(tokenKey);
    } catch {
      // kept in the page only
    }
  }

  // Shows the token field (a write or the list was refused for want of a token).
  askToken() {
    $("scenes-token-row").hidden = false;
  }

  refreshIfOpen() {
    if ($("your-scenes").open) this.refresh();
  }

  say(text, { error = false } = {}) {
    $("scenes-message").textContent = text || "";
    $("scenes-message").classList.toggle("error", error);
  }

  // Loads the first page again (or the next one, `more`), replacing (or extending) the list.
  refresh({ more = false } = {}) {
    const work = (async () => {
      this.say("Loading the list…");
      try {
        const page = await this.api.listScenes(more ? this.next : null);
        this.next = page.next;
        const rows = page.scenes.map((s) => this.row(s));
        if (more) $("scenes-list").append(...rows);
        else $("scenes-list").replaceChildren(...rows);
        $("scenes-more").hidden = !page.next;
        const count = $("scenes-list").children.length;
        this.say(count ? `${count}${page.next ? "+" : ""} stored scene${count === 1 ? "" : "s"}, newest first.`
          : "No stored scenes yet: Save stores the working scene.");
      } catch (error) {
        if (error.status === 401) this.askToken();
        if (!more) $("scenes-list").replaceChildren();
        $("scenes-more").hidden = true;
        this.say(listRefusal(error) ?? `The list could not be loaded: ${error.message}`, { error: true });
      } finally {
        // Tests (and people) can tell a list loaded again by this number.
        $("your-scenes").dataset.loads = String(Number($("your-scenes").dataset.loads || 0) + 1);
      }
    })();
    this.loading = work.finally(() => {
      if (this.loading === work) this.loading = null;
    });
    return work;
  }

  row(scene) {
    const li = document.createElement("li");
    li.dataset.id = scene.id;
    const name = document.createElement("span");
    name.className = "scene-id";
    name.textContent = scene.id;
    const size = document.createElement("span");
    size.textContent = formatBytes(scene.bytes);
    const when = document.createElement("time");
    when.dateTime = scene.created || "";
    when.textContent = scene.created ? new Date(scene.created).toLocaleString() : "";
    if (scene.expires) when.title = `Goes unless used again by ${new Date(scene.expires).toLocaleString()}`;
    const here = document.createElement("span");
    here.className = "note";
    here.textContent = this.isHere(scene.id) ? "open here" : "";
    const open = button("Open", `Open scene ${scene.id}`, () => this.open(scene.id));
    const del = button("Delete", `Delete scene ${scene.id}`, () => this.confirmDelete(li, scene.id));
    const actions = document.createElement("span");
    actions.className = "scene-actions";
    actions.append(open, del);
    li.append(name, size, when, here, actions);
    return li;
  }

  async open(id) {
    this.say(`Opening scene ${id}…`);
    try {
      await this.onOpen(id);
      this.say(`Opened scene ${id}: it is the working scene now.`);
      for (const li of $("scenes-list").children) li.querySelector(".note").textContent = this.isHere(li.dataset.id) ? "open here" : "";
    } catch (error) {
      const why = error.status === 404 ? "the server no longer has it (deleted, or expired)" : error.message;
      this.say(`Scene ${id} could not be opened: ${why}.`, { error: true });
    }
  }

  // The row asks first: Delete again deletes, Cancel (or Escape) keeps the scene. Focus goes to
  // Cancel, so a stray Enter deletes nothing.
  confirmDelete(li, id) {
    const actions = li.querySelector(".scene-actions");
    const before = [...actions.childNodes];
    const question = document.createElement("span");
    question.textContent = "Delete it from the server?";
    const restore = () => {
      actions.replaceChildren(...before);
      before[1].focus();
    };
    const yes = button("Delete", `Confirm: delete scene ${id}`, () => this.delete(id));
    yes.classList.add("danger");
    const no = button("Cancel", `Keep scene ${id}`, restore);
    actions.replaceChildren(question, yes, no);
    actions.addEventListener("keydown", function escape(e) {
      if (e.key !== "Escape" || !actions.contains(no)) return;
      e.preventDefault();
      e.stopPropagation();
      actions.removeEventListener("keydown", escape);
      restore();
    });
    no.focus();
  }

  async delete(id) {
    this.say(`Deleting scene ${id}…`);
    try {
      await this.api.deleteScene(id);
    } catch (error) {
      if (error.status === 401) this.askToken();
      const why = error.status === 401 ? "this server needs your access token for that (enter it above)"
        : error.status === 403 ? "this server does not let you delete it (it belongs to another token, or was stored before tokens were on)"
          : error.status === 404 ? "the server no longer has it" : error.message;
      this.say(`Scene ${id} was not deleted: ${why}.`, { error: true });
      if (error.status !== 404) return;
    }
    this.onDeleted(id);
    await this.refresh();
    this.say(`Deleted scene ${id}. ${$("scenes-message").textContent}`);
    $("scenes-refresh").focus();
  }
}

function button(text, label, onClick) {
  const b = document.createElement("button");
  b.type = "button";
  b.textContent = text;
  b.setAttribute("aria-label", label);
  b.addEventListener("click", onClick);
  return b;
}
