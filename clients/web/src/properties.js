// The properties panel. In: the selected element's JSON Pointer and value. Out: its fields
// ([{label, path, kind, value, min | exclusiveMin, max, step}], current values or the format's
// defaults) as inputs with the limits of schemas/scene.schema.json (fields.js; rotation any number),
// and the check of a typed value. A solid's fields come from its row of solid_types.js.
import { num, positive, nonNegative } from "./fields.js";
import { solidType } from "./solid_types.js";

function colorOf(c, fallback) {
  if (typeof c === "string" && /^#[0-9a-f]{6}$/i.test(c)) return c;
  if (Array.isArray(c)) return "#" + c.map((v) => Math.round(Math.max(0, Math.min(1, v)) * 255).toString(16).padStart(2, "0")).join("");
  return fallback;
}

function wallFields(w) {
  return [
    num("start x", ["start", 0], w.start[0]), num("start z", ["start", 1], w.start[1]),
    num("end x", ["end", 0], w.end[0]), num("end z", ["end", 1], w.end[1]),
    num("thickness", ["thickness"], w.thickness ?? 0.15, { ...positive, step: 0.01 }),
    num("height", ["height"], w.height ?? 2.5, positive),
    num("base", ["base"], w.base ?? 0),
    { label: "colour", path: ["color"], kind: "color", value: colorOf(w.color, "#e6e1d6") },
  ];
}

function openingFields(o) {
  const door = o.type === "door";
  const fields = [
    num("offset", ["offset"], o.offset, nonNegative),
    num("width", ["width"], o.width, positive),
    num("height", ["height"], o.height ?? (door ? 2.0 : 1.2), positive),
  ];
  if (!door) fields.push(num("sill", ["sill"], o.sill ?? 0.9, nonNegative));
  if (!door) fields.push(num("opacity", ["opacity"], o.opacity ?? 0.35, { min: 0, max: 1 }));
  if (door) fields.push({ label: "leaf", path: ["leaf"], kind: "bool", value: o.leaf ?? true });
  return fields;
}

function solidFields(s) {
  return [...solidType(s).fields(s), { label: "colour", path: ["color"], kind: "color", value: colorOf(s.color, "#b3b3b3") }];
}

function lightFields(l) {
  const fields = [];
  if (l.type === "point") {
    fields.push(num("x", ["position", 0], l.position[0]), num("y", ["position", 1], l.position[1]),
      num("z", ["position", 2], l.position[2]));
  } else {
    const d = l.direction || [0, -1, 0];
    fields.push(num("direction x", ["direction", 0], d[0], { step: 0.1 }), num("direction y", ["direction", 1], d[1], { step: 0.1 }),
      num("direction z", ["direction", 2], d[2], { step: 0.1 }));
  }
  fields.push(num("intensity", ["intensity"], l.intensity ?? 1, { ...nonNegative, step: 0.1 }));
  fields.push({ label: "colour", path: ["color"], kind: "color", value: colorOf(l.color, "#ffffff") });
  return fields.map((f) => (f.path[0] === "direction" ? { ...f, container: [0, -1, 0] } : f));
}

export function elementFields(pointer, element) {
  if (/\/openings\/\d+$/.test(pointer)) return openingFields(element);
  if (/^\/scene\/walls\/\d+$/.test(pointer)) return wallFields(element);
  if (/^\/scene\/solids\/\d+$/.test(pointer)) return solidFields(element);
  if (/^\/scene\/lights\/\d+$/.test(pointer)) return lightFields(element);
  return [];
}

// Why `value` is refused for `field`, or null.
export function fieldProblem(field, value) {
  if (field.kind !== "number") return null;
  const bad = !Number.isFinite(value) || (field.min !== undefined && value < field.min) ||
    (field.exclusiveMin !== undefined && value <= field.exclusiveMin) || (field.max !== undefined && value > field.max);
  if (!bad) return null;
  const limit = field.exclusiveMin !== undefined ? `> ${field.exclusiveMin}` : `≥ ${field.min}`;
  return `${field.label} must be ${limit}${field.max !== undefined ? ` and ≤ ${field.max}` : ""}`;
}

function input(field, onChange) {
  const label = document.createElement("label");
  label.textContent = field.label;
  const el = document.createElement("input");
  el.name = field.path.join(".");
  el.dataset.field = field.path.join("/");
  if (field.kind === "color") {
    el.type = "color";
    el.value = field.value;
  } else if (field.kind === "bool") {
    el.type = "checkbox";
    el.checked = field.value;
  } else {
    el.type = "number";
    el.step = field.step ?? 0.05;
    if (field.min !== undefined) el.min = field.min;
    if (field.max !== undefined) el.max = field.max;
    el.value = field.value;
  }
  el.addEventListener("change", () => onChange(field,
    field.kind === "bool" ? el.checked : field.kind === "color" ? el.value : Number(el.value)));
  label.append(el);
  return label;
}

// Fills `panel` with the element's fields; onChange(field, value) when one is changed.
export function renderProperties(panel, pointer, element, onChange) {
  if (element === undefined || element === null) {
    const note = document.createElement("p");
    note.className = "note";
    note.textContent = "Select an element in the plan (Select tool, V) to edit its fields.";
    panel.replaceChildren(note);
    return;
  }
  const title = document.createElement("h3");
  title.textContent = `${element.id || element.type || "wall"} — ${pointer}`;
  panel.replaceChildren(title, ...elementFields(pointer, element).map((f) => input(f, onChange)));
}
