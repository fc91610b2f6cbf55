// JSON Pointers (RFC 6901) against the text of a JSON document, through its Lezer syntax tree (the
// one CodeMirror's JSON mode builds; it tolerates syntax errors). In: document text and a pointer
// such as "/camera/fov_y". Out: character ranges in that text, and minimal text edits that set a
// value at a pointer while keeping the rest of the user's formatting. No DOM: runs in node tests.
import { parser } from "@lezer/json";

const valueTypes = new Set(["Object", "Array", "String", "Number", "True", "False", "Null"]);

export function parsePointer(pointer) {
  if (pointer === "") return [];
  if (!pointer.startsWith("/")) throw new Error(`not a JSON Pointer: ${pointer}`);
  return pointer.slice(1).split("/").map((t) => t.replace(/~1/g, "/").replace(/~0/g, "~"));
}

export function formatPointer(tokens) {
  return tokens.map((t) => "/" + String(t).replace(/~/g, "~0").replace(/\//g, "~1")).join("");
}

function children(node) {
  const out = [];
  for (let c = node.firstChild; c; c = c.nextSibling) out.push(c);
  return out;
}

function propertyName(text, nameNode) {
  const raw = text.slice(nameNode.from, nameNode.to);
  try {
    return JSON.parse(raw);
  } catch {
    return raw.replace(/^"|"$/g, "");
  }
}

// The Property nodes of an Object, each with its key and value node (null while the value is missing).
function properties(text, objectNode) {
  return children(objectNode)
    .filter((c) => c.name === "Property")
    .map((p) => {
      const parts = children(p);
      const name = parts.find((c) => c.name === "PropertyName");
      const value = parts.find((c) => valueTypes.has(c.name)) || null;
      return { node: p, nameNode: name, key: name ? propertyName(text, name) : "", value };
    });
}

function arrayItems(arrayNode) {
  return children(arrayNode).filter((c) => valueTypes.has(c.name));
}

export function parseTree(text) {
  return parser.parse(text);
}

function rootValue(tree) {
  const top = tree.topNode;
  return children(top).find((c) => valueTypes.has(c.name)) || null;
}

// Walks the pointer as far as the text goes. Returns {node, nameNode, depth, tokens}: the deepest
// value node reached, the PropertyName naming it (when it is an object member), and how many tokens
// were matched (depth === tokens.length when the whole pointer exists).
export function walkPointer(text, tree, pointer) {
  const tokens = parsePointer(pointer);
  let node = rootValue(tree);
  let nameNode = null;
  let depth = 0;
  if (!node) return { node: null, nameNode: null, depth: 0, tokens };
  for (const token of tokens) {
    let next = null;
    let nextName = null;
    if (node.name === "Object") {
      // A duplicated key is an error elsewhere; the last one is the one JSON.parse keeps.
      const match = properties(text, node).filter((p) => p.key === token).pop();
      if (match && match.value) {
        next = match.value;
        nextName = match.nameNode;
      } else if (match) {
        return { node, nameNode, depth, tokens, missingValueOf: match.nameNode };
      }
    } else if (node.name === "Array" && /^(0|[1-9][0-9]*)$/.test(token)) {
      next = arrayItems(node)[Number(token)] || null;
    }
    if (!next) break;
    node = next;
    nameNode = nextName;
    depth += 1;
  }
  return { node, nameNode, depth, tokens };
}

// The range to underline for an error at `pointer`: a scalar's own text; for an object or array its
// key (or its opening bracket when it has none), since underlining a whole wall hides what matters.
// A pointer that goes past the text (a missing member) marks the deepest existing part. `value` is
// the whole value's range (to tell whether it was edited since).
export function pointerRange(text, tree, pointer) {
  const walk = walkPointer(text, tree, pointer);
  if (walk.missingValueOf) {
    const { from, to } = walk.missingValueOf;
    return { from, to, exact: false, value: { from, to } };
  }
  const { node, nameNode, depth, tokens } = walk;
  if (!node) return { from: 0, to: Math.min(1, text.length), exact: false, value: { from: 0, to: text.length } };
  const exact = depth === tokens.length;
  const value = { from: node.from, to: node.to };
  if (node.name === "Object" || node.name === "Array") {
    if (nameNode) return { from: nameNode.from, to: nameNode.to, exact, value };
    return { from: node.from, to: node.from + 1, exact, value };
  }
  return { from: node.from, to: node.to, exact, value };
}

// The pointer of the innermost value at character offset `pos` (for status lines and tests).
export function pointerAt(text, tree, pos) {
  const tokens = [];
  let node = rootValue(tree);
  while (node && (node.name === "Object" || node.name === "Array")) {
    let next = null;
    if (node.name === "Object") {
      for (const p of properties(text, node)) {
        if (pos >= p.node.from && pos <= p.node.to && p.value) {
          tokens.push(p.key);
          next = p.value;
        }
      }
    } else {
      arrayItems(node).forEach((item, i) => {
        if (pos >= item.from && pos <= item.to) {
          tokens.push(String(i));
          next = item;
        }
      });
    }
    node = next;
  }
  return formatPointer(tokens);
}

function isScalar(v) {
  return v === null || typeof v !== "object";
}

// JSON text for `value`, indented to sit at `indent`: arrays of scalars stay on one line (as in
// examples/), objects get one member per line.
export function formatValue(value, indent = "", step = "  ") {
  if (isScalar(value)) return JSON.stringify(value);
  if (Array.isArray(value)) {
    if (value.every(isScalar)) return "[" + value.map((v) => JSON.stringify(v)).join(", ") + "]";
    if (value.length === 0) return "[]";
    const inner = indent + step;
    return "[\n" + value.map((v) => inner + formatValue(v, inner, step)).join(",\n") + "\n" + indent + "]";
  }
  const keys = Object.keys(value);
  if (keys.length === 0) return "{}";
  const inner = indent + step;
  return "{\n" + keys.map((k) => `${inner}${JSON.stringify(k)}: ${formatValue(value[k], inner, step)}`).join(",\n") +
    "\n" + indent + "}";
}

function lineIndent(text, pos) {
  const start = text.lastIndexOf("\n", pos - 1) + 1;
  return /^[ \t]*/.exec(text.slice(start))[0];
}

// A change {from, to, insert} that makes `pointer` hold `value` in `text`: the value's text is
// replaced when it exists; otherwise the missing members are inserted, nested, into the deepest
// existing object. Returns null when that cannot be done without guessing (the path runs into an
// array index that does not exist, a scalar, or text that does not parse as an object).
export function setAtPointer(text, tree, pointer, value) {
  const walk = walkPointer(text, tree, pointer);
  const { node, depth, tokens } = walk;
  if (!node) return null;
  if (walk.missingValueOf) {
    const at = walk.missingValueOf;
    const colon = text.indexOf(":", at.to);
    if (colon < 0) return null;
    let rest = value;
    for (let i = tokens.length - 1; i > depth; i--) rest = { [tokens[i]]: rest };
    return { from: colon + 1, to: colon + 1, insert: " " + formatValue(rest, lineIndent(text, at.from)) };
  }
  if (depth === tokens.length) {
    return { from: node.from, to: node.to, insert: formatValue(value, lineIndent(text, node.from)) };
  }
  if (node.name !== "Object") return null;
  let rest = value;
  for (let i = tokens.length - 1; i > depth; i--) rest = { [tokens[i]]: rest };
  const key = tokens[depth];
  const members = properties(text, node);
  const closing = node.to - 1;  // the "}" (an unterminated object has none: refuse)
  if (text[closing] !== "}") return null;
  if (members.length === 0) {
    const indent = lineIndent(text, node.from);
    const inner = indent + "  ";
    return { from: node.from + 1, to: closing,
      insert: `\n${inner}${JSON.stringify(key)}: ${formatValue(rest, inner)}\n${indent}` };
  }
  const last = members[members.length - 1].node;
  const multiline = text.slice(node.from, node.to).includes("\n");
  const indent = multiline ? lineIndent(text, last.from) : "";
  const sep = multiline ? ",\n" + indent : ", ";
  return { from: last.to, to: last.to, insert: `${sep}${JSON.stringify(key)}: ${formatValue(rest, indent)}` };
}

export function applyChange(text, change) {
  return text.slice(0, change.from) + change.insert + text.slice(change.to);
}
