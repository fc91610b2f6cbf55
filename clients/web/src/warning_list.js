// The answer's placement warnings as a collapsible list under the editor, filtered by kind. In: the
// warnings ({pointer, detail}, pointers into the request) and what a click on one does (reveal it in
// the editor, select it in the plan). Out: the #warnings box's contents.
const $ = (id) => document.getElementById(id);

// A warning's kind, for the filter: which check it comes from, read from its pointer and text.
function warningKind({ pointer, detail }) {
  if (/\/openings\//.test(pointer || "")) return "openings";
  if (/floor/i.test(detail)) return "beyond the floor";
  if (/\/solids\//.test(pointer || "") && /wall/i.test(detail)) return "solid and wall";
  if (/\/solids\//.test(pointer || "")) return "solids";
  return "other";
}

// The answer's placement warnings: drawn on their elements in the plan, and listed in a collapsible
// list filtered by kind (open by itself while it is short).
export function showWarningList(warnings, extraCount, { reveal, select: selectInPlan }) {
  const box = $("warnings");
  const select = $("warning-kind");
  const kinds = [...new Set(warnings.map(warningKind))].sort();
  const wanted = kinds.includes(select.value) ? select.value : "";
  select.replaceChildren(new Option(`all (${warnings.length})`, ""),
    ...kinds.map((k) => new Option(`${k} (${warnings.filter((w) => warningKind(w) === k).length})`, k)));
  select.value = wanted;
  const total = warnings.length || extraCount;
  box.hidden = total === 0;
  $("warnings-summary").textContent = `${total} placement warning${total === 1 ? "" : "s"}`;
  if (warnings.length <= 5) box.open = true;
  const list = $("warning-list");
  list.replaceChildren();
  for (const w of warnings) {
    if (select.value && warningKind(w) !== select.value) continue;
    const li = document.createElement("li");
    li.className = "warning";
    li.dataset.kind = warningKind(w);
    const link = document.createElement("button");
    link.type = "button";
    link.className = "pointer";
    link.textContent = w.pointer;
    link.title = "Show this element in the editor and select it in the plan";
    link.addEventListener("click", () => {
      reveal(w.pointer);
      const element = /^\/scene\/(walls\/\d+(\/openings\/\d+)?|solids\/\d+|lights\/\d+)/.exec(w.pointer);
      if (element) selectInPlan(element[0]);
    });
    li.append(link, " ", w.detail);
    list.append(li);
  }
  if (!warnings.length && extraCount) {
    const li = document.createElement("li");
    li.className = "warning";
    li.textContent = `${extraCount} placement warning(s); this server lists them only in JSON answers.`;
    list.append(li);
  }
}
