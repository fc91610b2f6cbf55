// The request editor: CodeMirror 6 with JSON highlighting and one diagnostics source that merges
// JSON syntax errors, schema errors as the user types (when the server publishes its schemas) and
// the server's own problem+json errors and placement warnings. Every diagnostic is kept as a JSON
// Pointer and placed on the text each time the linter runs, so it follows the field through edits;
// each is underlined and its message is written at the end of the field's line.
import { EditorState, Prec, StateEffect } from "@codemirror/state";
import { EditorView, Decoration, ViewPlugin, WidgetType, keymap, lineNumbers, highlightActiveLine,
  highlightActiveLineGutter, drawSelection } from "@codemirror/view";
import { defaultKeymap, history, historyKeymap } from "@codemirror/commands";
import { syntaxHighlighting, defaultHighlightStyle, bracketMatching, foldGutter, foldKeymap,
  indentOnInput } from "@codemirror/language";
import { json } from "@codemirror/lang-json";
import { linter, lintGutter, lintKeymap, forceLinting, forEachDiagnostic, setDiagnosticsEffect } from "@codemirror/lint";
import { parseTree, pointerRange, setAtPointer, applyChange } from "./json_pointer.js";

// Asks the linter to run again although the text did not change (new server notes arrived).
// forceLinting alone runs only a lint that is already pending: once the last one has finished, it
// does nothing, and notes that arrive after it would wait for the next keystroke.
const relint = StateEffect.define();

class InlineMessage extends WidgetType {
  constructor(text, severity) {
    super();
    this.text = text;
    this.severity = severity;
  }
  eq(other) {
    return other.text === this.text && other.severity === this.severity;
  }
  toDOM() {
    const span = document.createElement("span");
    span.className = `cm-inline-message cm-inline-${this.severity}`;
    span.textContent = this.text;
    return span;
  }
}

// The messages of each line's diagnostics, written after the line's text.
function inlineMessages(view) {
  const byLine = new Map();
  forEachDiagnostic(view.state, (d, from) => {
    const line = view.state.doc.lineAt(from);
    const entry = byLine.get(line.number) || { to: line.to, texts: [], severity: "warning" };
    entry.texts.push(d.message);
    if (d.severity === "error") entry.severity = "error";
    byLine.set(line.number, entry);
  });
  const widgets = [...byLine.values()].sort((a, b) => a.to - b.to).map((e) =>
    Decoration.widget({ widget: new InlineMessage(e.texts.join("; "), e.severity), side: 1 }).range(e.to));
  return Decoration.set(widgets);
}

const inlineMessagePlugin = ViewPlugin.fromClass(class {
  constructor(view) {
    this.decorations = inlineMessages(view);
  }
  update(update) {
    if (update.docChanged || update.transactions.some((tr) => tr.effects.some((e) => e.is(setDiagnosticsEffect)))) {
      this.decorations = inlineMessages(update.view);
    }
  }
}, { decorations: (v) => v.decorations });

// JSON.parse's message, placed at the first error node of the syntax tree (or the position the
// message names).
function syntaxDiagnostic(text, tree, error) {
  let at = null;
  tree.iterate({ enter(n) {
    if (at === null && n.type.isError) at = n.from;
    return at === null;
  } });
  if (at === null) {
    const m = /position (\d+)/.exec(error.message);
    at = m ? Number(m[1]) : 0;
  }
  const from = Math.min(at, Math.max(0, text.length - 1));
  return { from, to: Math.min(text.length, from + 1), severity: "error", source: "JSON",
    message: error.message.replace(/^JSON\.parse: /, "") };
}

export class RequestEditor {
  constructor(parent, { onChange, onRun }) {
    this.checker = null;       // (request) => [{pointer, message}] once the schemas are known
    this.serverNotes = [];     // [{pointer, message, severity, valueText}] from the last answer
    this.onChange = onChange;
    const runKeys = Prec.highest(keymap.of([{ key: "Mod-Enter", run: () => (onRun(), true) }]));
    this.view = new EditorView({
      parent,
      state: EditorState.create({
        doc: "",
        extensions: [
          runKeys, lineNumbers(), highlightActiveLineGutter(), foldGutter(), history(), drawSelection(),
          indentOnInput(), bracketMatching(), highlightActiveLine(),
          syntaxHighlighting(defaultHighlightStyle, { fallback: true }), json(),
          keymap.of([...defaultKeymap, ...historyKeymap, ...foldKeymap, ...lintKeymap]),
          linter((view) => this.diagnostics(view.state.doc.toString()), { delay: 250,
            needsRefresh: (u) => u.transactions.some((tr) => tr.effects.some((e) => e.is(relint))) }),
          lintGutter(), inlineMessagePlugin,
          EditorView.contentAttributes.of({ "aria-label": "Render request (JSON)" }),
          EditorView.updateListener.of((u) => { if (u.docChanged) this.onChange(this.text()); }),
        ],
      }),
    });
  }

  text() {
    return this.view.state.doc.toString();
  }

  // The document (immutable: a new one after each change), for caches keyed on the text.
  doc() {
    return this.view.state.doc;
  }

  // Replaces the whole document (an example or an import), as one undoable step.
  setText(text) {
    this.serverNotes = [];
    this.view.dispatch({ changes: { from: 0, to: this.view.state.doc.length, insert: text },
      selection: { anchor: 0 }, scrollIntoView: true });
  }

  // Parsed request, or null while the text is not JSON.
  parsed() {
    try {
      return JSON.parse(this.text());
    } catch {
      return null;
    }
  }

  // Sets several members by JSON Pointer ([{pointer, value}]) as one edit that keeps the rest of the
  // text as written. Returns false when a pointer cannot be set without guessing.
  setValues(entries) {
    const before = this.text();
    let text = before;
    for (const { pointer, value } of entries) {
      const change = setAtPointer(text, parseTree(text), pointer, value);
      if (!change) return false;
      text = applyChange(text, change);
    }
    this.replaceText(text);
    return true;
  }

  // Replaces the text by `text`, changing only the stretch between their common start and end, so the
  // view and the cursor stay where they are (one undoable step of the editor's own history).
  replaceText(text) {
    const before = this.text();
    if (text === before) return;
    let start = 0;
    while (start < text.length && start < before.length && text[start] === before[start]) start++;
    let end = 0;
    while (end < text.length - start && end < before.length - start &&
           text[text.length - 1 - end] === before[before.length - 1 - end]) end++;
    this.view.dispatch({ changes: { from: start, to: before.length - end, insert: text.slice(start, text.length - end) },
      userEvent: "input.set" });
  }

  setChecker(checker) {
    this.checker = checker;
    this.relintNow();
  }

  relintNow() {
    this.view.dispatch({ effects: relint.of(null) });
    forceLinting(this.view);
  }

  // Errors and warnings from the server, by pointer. Each stays until the next answer, or until the
  // text of its value changes (the user is fixing it; for an object, anything inside it).
  setServerNotes(notes) {
    const text = this.text();
    const tree = parseTree(text);
    this.serverNotes = notes.map((n) => {
      const r = n.pointer === null ? null : pointerRange(text, tree, n.pointer);
      return { ...n, valueText: r ? text.slice(r.value.from, r.value.to) : null };
    });
    this.relintNow();
  }

  diagnostics(text) {
    const tree = parseTree(text);
    const out = [];
    let request = null;
    try {
      request = JSON.parse(text);
    } catch (error) {
      if (text.trim() !== "") out.push(syntaxDiagnostic(text, tree, error));
    }
    const place = (pointer, message, severity, source) => {
      const r = pointerRange(text, tree, pointer);
      out.push({ from: r.from, to: Math.max(r.to, r.from + 1), severity, source, message });
      return r;
    };
    if (request !== null && this.checker) {
      for (const d of this.checker(request)) place(d.pointer, d.message, "error", "schema");
    }
    this.serverNotes = this.serverNotes.filter((n) => {
      if (n.pointer === null) return true;  // shown in the list under the editor only
      const r = pointerRange(text, tree, n.pointer);
      if (n.valueText !== null && text.slice(r.value.from, r.value.to) !== n.valueText) return false;
      place(n.pointer, n.message, n.severity, "server");
      return true;
    });
    return out.filter((d) => d.to <= text.length || text.length === 0).map((d) => ({ ...d, to: Math.min(d.to, text.length) }));
  }

  // Puts the cursor on the field a pointer names and scrolls it into view.
  reveal(pointer) {
    const text = this.text();
    const r = pointerRange(text, parseTree(text), pointer ?? "");
    this.view.dispatch({ selection: { anchor: r.from, head: r.to }, scrollIntoView: true });
    this.view.focus();
  }
}
