// The game service's HTTP API (docs/protocol.md): JSON in and out, the player's token kept in
// localStorage so that it survives a reload, and refusals raised as ApiError {code, reason}.

const TOKEN_KEY = "billiards.token";
const PLAYER_KEY = "billiards.player";

export class ApiError extends Error {
  constructor(status, body) {
    super(body?.reason ?? `HTTP ${status}`);
    this.status = status;
    this.code = body?.code ?? "http_error";
  }
}

export function token() {
  return localStorage.getItem(TOKEN_KEY);
}

/** The stored player {id, name}, or null. */
export function storedPlayer() {
  try {
    return JSON.parse(localStorage.getItem(PLAYER_KEY));
  } catch {
    return null;
  }
}

/** `method path` with an optional JSON body; resolves to the parsed answer (null if empty). */
export async function call(method, path, body) {
  const headers = { Accept: "application/json" };
  const t = token();
  if (t) headers.Authorization = `Bearer ${t}`;
  if (body !== undefined) headers["Content-Type"] = "application/json";
  const response = await fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  const text = await response.text();
  let data = null;
  try {
    data = text ? JSON.parse(text) : null;
  } catch {
    data = { reason: text };
  }
  if (!response.ok) throw new ApiError(response.status, data);
  return data;
}

export const get = (path) => call("GET", path);
export const post = (path, body = {}) => call("POST", path, body);

/** The stored player if its token is still good (GET /api/me), else null (and forget it). */
export async function currentPlayer() {
  if (!token()) return null;
  try {
    const me = await get("/api/me");
    localStorage.setItem(PLAYER_KEY, JSON.stringify(me));
    return me;
  } catch (e) {
    if (e.status === 401) {
      localStorage.removeItem(TOKEN_KEY);
      localStorage.removeItem(PLAYER_KEY);
      return null;
    }
    throw e;
  }
}

/** Become player `name` (POST /api/players) and keep the token. */
export async function register(name) {
  const answer = await post("/api/players", { name });
  localStorage.setItem(TOKEN_KEY, answer.token);
  localStorage.setItem(PLAYER_KEY, JSON.stringify(answer.player));
  return answer.player;
}

/** A fresh shot id (8-64 of A-Z a-z 0-9 _ -). */
export function shotId() {
  const bytes = crypto.getRandomValues(new Uint8Array(16));
  return Array.from(bytes, (b) => b.toString(16).padStart(2, "0")).join("");
}
