// The designer's undo history over whole request texts. In: the text before and after each step.
// Out: the text to show after an undo or a redo. `committed` is the text of the last step; a text
// that differs from it is an edit in progress (typing), which becomes a step of its own when it is
// settled (settle) — so an undo first keeps it, then goes back past it. Pure: no DOM, no editor.
export class History {
  constructor(text = "") {
    this.undo = [];
    this.redo = [];
    this.committed = text;
  }

  // A step from `before` to `after` (a designer edit, or typing that rested).
  record(before, after) {
    if (before === after) return;
    this.undo.push(before);
    this.redo = [];
    this.committed = after;
  }

  // Typing became `text`: one step when it differs from the last one. `valid`: only a request that
  // parses is a step (half-typed JSON is not a state to go back to).
  settle(text, valid = true) {
    if (text !== this.committed && valid) this.record(this.committed, text);
  }

  // The new text (or null when there is nothing to undo); `current` goes onto the other stack, so a
  // redo brings back even text that did not parse.
  back(current) {
    return this.move(this.undo, this.redo, current);
  }

  forward(current) {
    return this.move(this.redo, this.undo, current);
  }

  move(from, to, current) {
    if (!from.length) return null;
    to.push(current);
    this.committed = from.pop();
    return this.committed;
  }

  // Text that changed without being a step (a camera move): the last step now reads `text`.
  amend(text) {
    this.committed = text;
  }

  // A fresh start (a restored scene): nothing to undo.
  reset(text) {
    this.undo = [];
    this.redo = [];
    this.committed = text;
  }
}
