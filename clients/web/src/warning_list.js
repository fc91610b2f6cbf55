// The answer's placement warnings as a collapsible list under the editor, one entry per element
// (a piece of furniture, a wall, an opening) with its warnings under it, deepest first as the server
// sorts them, filtered by kind. In: the warnings ({pointer, detail, depth, other}, pointers into the
// request), the total the server counted, a label for an element, and what a click on one does
// (reveal it in the editor, select it in the plan). Out: the #warnings box's contents.
const $ = (id) => document.getElementById(id);

// A warning's kind, for the filter: which check it comes from, read from its pointer and text.
function warningKind({ pointer, detail }) {
  if (/\/openings\//.test(pointer || "")) return "openings";
  if (/floor/i.test(detail)) return "beyond the floor";
  if (/\/solids\//.test(pointer || "") && /intersects wall/i.test(detail)) return "solid and wall";
  if (/\/solids\//.test(pointer || "")) return "solids";
  return "other";
}

const elementOf = (pointer) => /^\/scene\/(walls\/\d+(\/openings\/\d+)?|solids\/\d+|lights\/\d+)/.exec(pointer || "")?.[0] ?? null;

// Warnings grouped by the element they are about, in the order of each element's first (deepest)
// warning: [{pointer, warnings}].
export function groupByElement(warnings) {
  const groups = new Map();
  for (const w of warnings) {
    const key = w.pointer ?? "";
    if (!groups.has(key)) groups.set(key, { pointer: w.pointer, warnings: [] });
    groups.get(key).warnings.push(w);
  }
  return [...groups.values()];
}

// The answer's placement warnings: drawn on their elements in the plan, and listed per element in a
// collapsible list filtered by kind (open by itself while it is short). `total`: the problems the
// server counted (it lists the deepest only); `label(pointer)`: how an element is named.
export function showWarningList(warnings, total, { reveal, select: selectInPlan, label = (p) => p }) {
  const box = $("warnings");
  const select = $("warning-kind");
  const kinds = [...new Set(warnings.map(warningKind))].sort();
  const wanted = kinds.includes(select.value) ? select.value : "";
  select.replaceChildren(new Option(`all (${warnings.length})`, ""),
    ...kinds.map((k) => new Option(`${k} (${warnings.filter((w) => warningKind(w) === k).length})`, k)));
  select.value = wanted;
  const count = Math.max(total, warnings.length);
  box.hidden = count === 0;
  $("warnings-summary").textContent = `${count} placement warning${count === 1 ? "" : "s"}`;
  if (warnings.length <= 5) box.open = true;
  const list = $("warning-list");
  list.replaceChildren();
  for (const group of groupByElement(warnings.filter((w) => !select.value || warningKind(w) === select.value))) {
    const li = document.createElement("li");
    li.className = "warning";
    li.dataset.kind = warningKind(group.warnings[0]);
    const link = document.createElement("button");
    link.type = "button";
    link.className = "pointer";
    link.textContent = label(group.pointer);
    link.title = `${group.pointer}: show it in the editor and select it in the plan`;
    link.addEventListener("click", () => {
      reveal(group.pointer);
      const element = elementOf(group.pointer);
      if (element) selectInPlan(element);
    });
    const details = document.createElement("ul");
    for (const w of group.warnings) {
      const item = document.createElement("li");
      item.textContent = w.detail;
      details.append(item);
    }
    li.append(link, details);
    list.append(li);
  }
  if (!warnings.length && total) {
    const li = document.createElement("li");
    li.className = "warning";
    li.textContent = `${total} placement warning(s); this server lists them only in JSON answers.`;
    list.append(li);
  }
}
