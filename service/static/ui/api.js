// The service's HTTP API as the workbench uses it: JSON, multipart execution, binary results.

const KEY = "morphserve.apiKey";

export function apiKey() {
  return localStorage.getItem(KEY) || "";
}

export function setApiKey(value) {
  if (value) localStorage.setItem(KEY, value);
  else localStorage.removeItem(KEY);
}

function headers(extra = {}) {
  const h = { ...extra };
  const key = apiKey();
  if (key) h.Authorization = `Bearer ${key}`;
  return h;
}

/** An error of the service: its problem document (RFC 9457) when it sent one. */
export class ProblemError extends Error {
  constructor(status, problem) {
    super(problem?.detail || problem?.title || `HTTP ${status}`);
    this.status = status;
    this.problem = problem || {};
  }
}

async function check(response) {
  if (response.ok) return response;
  let problem = null;
  try { problem = await response.json(); } catch { /* not JSON */ }
  throw new ProblemError(response.status, problem);
}

export async function getJSON(path, extraHeaders = {}) {
  const r = await check(await fetch(path, { headers: headers({ Accept: "application/json", ...extraHeaders }) }));
  return r.json();
}

export async function getBinary(path, accept) {
  const r = await check(await fetch(path, { headers: headers({ Accept: accept }) }));
  return r.arrayBuffer();
}

/**
 * Starts a job: POST /processes/{id}/execution with Prefer: respond-async. With files, the
 * body is multipart: a "spec" part holding {"inputs": ...} and one part per file, named
 * after its input; else JSON. Returns the job's statusInfo.
 */
export async function execute(processId, inputs, files) {
  const url = `/processes/${encodeURIComponent(processId)}/execution`;
  const spec = JSON.stringify({ inputs });
  let init;
  if (files.size) {
    const form = new FormData();
    form.append("spec", new Blob([spec], { type: "application/json" }), "spec.json");
    for (const [name, file] of files) form.append(name, file, file.name);
    init = { method: "POST", body: form, headers: headers({ Prefer: "respond-async" }) };
  } else {
    init = {
      method: "POST", body: spec,
      headers: headers({ "Content-Type": "application/json", Prefer: "respond-async" }),
    };
  }
  const r = await check(await fetch(url, init));
  return r.json();
}

export async function dismiss(jobId) {
  const r = await check(await fetch(`/jobs/${encodeURIComponent(jobId)}`,
    { method: "DELETE", headers: headers() }));
  return r.json();
}

/**
 * A typed binary array of a results document ({"dtype", "shape", "data": base64}) as a
 * typed array with its shape; JSON lists pass through as they are.
 */
export function decodeArray(value) {
  if (!value || typeof value !== "object" || typeof value.data !== "string" || !value.dtype) {
    return null;
  }
  const raw = atob(value.data);
  const bytes = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
  const kinds = {
    "<f8": Float64Array, "<f4": Float32Array, "<i8": BigInt64Array, "<i4": Int32Array,
    "<i2": Int16Array, "|i1": Int8Array, "<u8": BigUint64Array, "<u4": Uint32Array,
    "<u2": Uint16Array, "|u1": Uint8Array,
  };
  const T = kinds[value.dtype];
  if (!T) return null;
  let arr = new T(bytes.buffer);
  if (arr instanceof BigInt64Array || arr instanceof BigUint64Array) {
    arr = Float64Array.from(arr, Number);
  }
  return { data: arr, shape: value.shape };
}

/** Whether a results value is an array (typed binary or a JSON list). */
export function isArrayValue(value) {
  return Array.isArray(value) || (value && typeof value === "object" && typeof value.data === "string"
    && Array.isArray(value.shape));
}
