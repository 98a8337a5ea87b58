// A form generated from a process description's inputs (their OpenAPI 3.0 schemas, as the
// OGC process description gives them): selects for choices, number fields with the bounds,
// checkboxes, defaults filled; array and object inputs (geometry, labels, graphs) by file
// (drag and drop, or the file picker) or as pasted JSON.

const FILE_TYPES = ".ply,.obj,.stl,.off,.glb,.npy,.json";

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === "class") e.className = v;
    else if (k === "text") e.textContent = v;
    else e.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children) if (c) e.append(c);
  return e;
}

function members(schema) {
  return schema.oneOf || schema.anyOf || null;
}

function isScalar(schema) {
  if (schema.enum) return true;
  const m = members(schema);
  if (m) return m.every(isScalar);
  return ["number", "integer", "string", "boolean"].includes(schema.type);
}

/** How an input is edited: "enum", "number", "boolean", "text", "scalars", "choice+data", "data". */
export function widgetKind(schema) {
  if (schema.enum) return "enum";
  const m = members(schema);
  if (m) {
    if (m.every(isScalar)) return "scalars";
    if (m.some((s) => s.enum) && m.some((s) => !isScalar(s))) return "choice+data";
    return "data";
  }
  if (schema.type === "integer" || schema.type === "number") return "number";
  if (schema.type === "boolean") return "boolean";
  if (schema.type === "string") return "text";
  return "data";
}

function boundsText(schema) {
  const parts = [];
  if (schema.minimum !== undefined) parts.push(`${schema.exclusiveMinimum ? ">" : "≥"} ${schema.minimum}`);
  if (schema.maximum !== undefined) parts.push(`${schema.exclusiveMaximum ? "<" : "≤"} ${schema.maximum}`);
  return parts.join(", ");
}

const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

/** One input's field: its element, and how to read, set and reset its value. */
class Field {
  constructor(name, input) {
    this.name = name;
    this.input = input;
    this.schema = input.schema || {};
    this.required = (input.minOccurs ?? 0) > 0;
    this.kind = widgetKind(this.schema);
    this.file = null;
    this.element = this.build();
    this.reset();
  }

  build() {
    const id = `in-${this.name}`;
    const s = this.schema;
    const label = el("label", { for: id, text: this.input.title || this.name });
    if (this.required) label.append(el("span", { class: "req", text: "*", "aria-label": "required" }));
    const descId = `${id}-desc`;
    const bounds = boundsText(s);
    const desc = el("div", { class: "desc", id: descId,
      text: [this.input.description, bounds && `(${bounds})`].filter(Boolean).join(" ") });
    this.error = el("div", { class: "invalid", role: "status" });
    const box = el("div", { class: "field", "data-input": this.name, "data-kind": this.kind }, label, desc);
    const common = { id, name: this.name, "aria-describedby": descId };
    if (this.kind === "enum") {
      this.control = el("select", common);
      if (!this.required && s.default === undefined) this.control.append(el("option", { value: "", text: "—" }));
      for (const v of s.enum) this.control.append(el("option", { value: JSON.stringify(v), text: String(v) }));
      box.append(this.control);
    } else if (this.kind === "number") {
      const integer = s.type === "integer";
      this.control = el("input", { ...common, type: "number", step: integer ? "1" : "any",
        min: s.minimum, max: s.maximum, required: this.required });
      box.append(this.control);
    } else if (this.kind === "boolean") {
      this.control = el("input", { ...common, type: "checkbox" });
      label.prepend(this.control);
      label.setAttribute("for", id);
    } else if (this.kind === "text" || this.kind === "scalars") {
      this.control = el("input", { ...common, type: "text", spellcheck: "false" });
      const choices = (members(s) || []).flatMap((m) => m.enum || []);
      if (choices.length) {
        const list = el("datalist", { id: `${id}-list` });
        for (const c of choices) list.append(el("option", { value: String(c) }));
        this.control.setAttribute("list", `${id}-list`);
        box.append(list);
      }
      box.append(this.control);
    } else {
      if (this.kind === "choice+data") {
        this.choice = el("select", { id: `${id}-choice`, "aria-label": `${this.input.title || this.name}: choice` });
        for (const v of members(s).flatMap((m) => m.enum || [])) {
          this.choice.append(el("option", { value: JSON.stringify(v), text: String(v) }));
        }
        this.choice.append(el("option", { value: "__json__", text: "value (JSON)…" }));
        this.choice.addEventListener("change", () => { this.textarea.hidden = this.choice.value !== "__json__"; });
        box.append(this.choice);
      } else {
        this.dropzone = this.buildDrop(id);
        box.append(this.dropzone);
      }
      this.textarea = el("textarea", { ...common, spellcheck: "false",
        placeholder: "JSON, e.g. [[0, 0, 0], [1, 0, 0], …]" });
      this.control = this.textarea;
      box.append(this.textarea);
    }
    box.append(this.error);
    return box;
  }

  buildDrop(id) {
    const fileInput = el("input", { type: "file", id: `${id}-file`, accept: FILE_TYPES,
      "aria-label": `${this.input.title || this.name}: file`, "data-input-file": this.name });
    const name = el("span", { class: "file-name" });
    const clear = el("button", { type: "button", class: "secondary", text: "Clear", hidden: true });
    const zone = el("div", { class: "drop" }, el("span", { text: "Drop a PLY, OBJ, STL, OFF, GLB or NPY file here, or" }),
      fileInput, name, clear);
    const take = (file) => {
      this.file = file || null;
      name.textContent = file ? `${file.name} (${(file.size / 1024).toFixed(1)} kB)` : "";
      clear.hidden = !file;
      this.textarea.disabled = Boolean(file);
    };
    fileInput.addEventListener("change", () => take(fileInput.files[0]));
    clear.addEventListener("click", () => { fileInput.value = ""; take(null); });
    zone.addEventListener("dragover", (e) => { e.preventDefault(); zone.classList.add("over"); });
    zone.addEventListener("dragleave", () => zone.classList.remove("over"));
    zone.addEventListener("drop", (e) => {
      e.preventDefault();
      zone.classList.remove("over");
      if (e.dataTransfer.files.length) take(e.dataTransfer.files[0]);
    });
    this.takeFile = take;
    this.fileInput = fileInput;
    return zone;
  }

  reset() {
    this.set(this.schema.default);
    if (this.takeFile) { this.fileInput.value = ""; this.takeFile(null); }
  }

  set(value) {
    this.error.textContent = "";
    if (this.kind === "enum") {
      this.control.value = value === undefined ? (this.control.options[0]?.value ?? "") : JSON.stringify(value);
    } else if (this.kind === "boolean") {
      this.control.checked = Boolean(value);
    } else if (this.kind === "number" || this.kind === "text") {
      this.control.value = value === undefined || value === null ? "" : String(value);
    } else if (this.kind === "scalars") {
      this.control.value = value === undefined || value === null ? "" : String(value);
    } else if (this.kind === "choice+data") {
      const opt = [...this.choice.options].find((o) => o.value === JSON.stringify(value));
      if (opt || value === undefined) {
        this.choice.value = opt ? opt.value : this.choice.options[0].value;
        this.textarea.value = "";
      } else {
        this.choice.value = "__json__";
        this.textarea.value = JSON.stringify(value);
      }
      this.textarea.hidden = this.choice.value !== "__json__";
    } else {
      if (this.takeFile && value !== undefined) { this.fileInput.value = ""; this.takeFile(null); }
      this.textarea.value = value === undefined || value === null ? "" : JSON.stringify(value);
    }
  }

  /** The value to send: {value} when given, {} when left out; throws with a message. */
  read() {
    this.error.textContent = "";
    const s = this.schema;
    let value;
    if (this.kind === "enum") {
      if (this.control.value === "") return {};
      value = JSON.parse(this.control.value);
    } else if (this.kind === "boolean") {
      value = this.control.checked;
    } else if (this.kind === "number") {
      const text = this.control.value.trim();
      if (text === "") return this.missing();
      value = Number(text);
      if (!Number.isFinite(value)) throw this.fail("Expected a number.");
      if (s.type === "integer" && !Number.isInteger(value)) throw this.fail("Expected a whole number.");
      const lo = s.minimum, hi = s.maximum;
      if (lo !== undefined && (s.exclusiveMinimum ? value <= lo : value < lo)) throw this.fail(`Expected a number ${boundsText(s)}.`);
      if (hi !== undefined && (s.exclusiveMaximum ? value >= hi : value > hi)) throw this.fail(`Expected a number ${boundsText(s)}.`);
    } else if (this.kind === "text") {
      if (this.control.value === "") return this.missing();
      value = this.control.value;
    } else if (this.kind === "scalars") {
      const text = this.control.value.trim();
      if (text === "") return this.missing();
      const n = Number(text);
      value = text !== "" && Number.isFinite(n) ? n : text === "true" ? true : text === "false" ? false : text;
    } else if (this.kind === "choice+data" && this.choice.value !== "__json__") {
      value = JSON.parse(this.choice.value);
    } else {
      if (this.file) return { file: this.file };
      const text = this.textarea.value.trim();
      if (text === "") return this.missing();
      try { value = JSON.parse(text); } catch (e) { throw this.fail(`Not valid JSON: ${e.message}`); }
    }
    if (!this.required && s.default !== undefined && same(value, s.default)) return {};
    return { value };
  }

  missing() {
    if (this.required) throw this.fail("Required: give a value.");
    return {};
  }

  fail(message) {
    this.error.textContent = message;
    const e = new Error(`${this.name}: ${message}`);
    e.field = this.name;
    return e;
  }
}

/** The form of a process: fields by input name; read() gives {inputs, files}. */
export class ProcessForm {
  constructor(container, description) {
    this.fields = new Map();
    container.replaceChildren();
    const inputs = Object.entries(description.inputs || {});
    // required inputs first, in the description's order otherwise
    inputs.sort((a, b) => (b[1].minOccurs ?? 0) - (a[1].minOccurs ?? 0));
    const more = el("details", { class: "more" }, el("summary", { text: "Options" }));
    for (const [name, input] of inputs) {
      const f = new Field(name, input);
      this.fields.set(name, f);
      (f.required ? container : more).append(f.element);
    }
    const optional = more.children.length - 1;
    if (optional) {
      more.firstChild.textContent = `Options (${optional}, defaults filled)`;
      container.append(more);
    }
    if (!inputs.length) container.append(el("p", { class: "info", text: "This process takes no inputs." }));
  }

  fill(example) {
    for (const f of this.fields.values()) f.reset();
    for (const [name, value] of Object.entries(example || {})) this.fields.get(name)?.set(value);
  }

  read() {
    const inputs = {};
    const files = new Map();
    const errors = [];
    for (const [name, f] of this.fields) {
      try {
        const r = f.read();
        if ("file" in r) files.set(name, r.file);
        else if ("value" in r) inputs[name] = r.value;
      } catch (e) {
        errors.push(e);
      }
    }
    if (errors.length) {
      const e = new Error(errors.map((x) => x.message).join("\n"));
      e.fields = errors.map((x) => x.field);
      throw e;
    }
    return { inputs, files };
  }

  showErrors(problem) {
    for (const err of problem?.errors || []) {
      const head = String(err.input || "").split(/[.[]/)[0];
      const f = this.fields.get(head);
      if (f) f.error.textContent = err.message;
    }
  }
}
