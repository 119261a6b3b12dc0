// A job's server-sent events over fetch (EventSource cannot send the API
// key), reconnecting by itself with Last-Event-ID after a dropped
// connection, so no event is lost or seen twice.

import { headers } from "./api.js";

const FINAL = new Set(["done", "failed", "cancelled"]);

/**
 * Streams `/v1/jobs/{id}/events` to `onEvent({id, event, data})` until a
 * final event; `onState("live" | "reconnecting")` tells the connection's
 * state. Returns `{stop()}`, which ends the stream.
 */
export function followEvents(jobId, onEvent, onState = () => {}) {
  const controller = new AbortController();
  let last = null;
  let delay = 500;
  let ended = false;

  async function connect() {
    while (!ended && !controller.signal.aborted) {
      try {
        const extra = last ? { "Last-Event-ID": last } : {};
        const response = await fetch(`/v1/jobs/${jobId}/events`, {
          headers: headers({ Accept: "text/event-stream", ...extra }),
          signal: controller.signal,
          cache: "no-store",
        });
        if (response.status === 404 || response.status === 401) {
          onEvent({ id: null, event: "failed", data: { error: `events: HTTP ${response.status}` } });
          return;
        }
        if (!response.ok) throw new Error(`HTTP ${response.status}`);
        onState("live");
        delay = 500;
        await read(response.body, (message) => {
          last = message.id ?? last;
          if (FINAL.has(message.event)) ended = true;
          onEvent(message);
        });
      } catch (e) {
        if (controller.signal.aborted) return;
      }
      if (ended || controller.signal.aborted) return;
      onState("reconnecting");
      await new Promise((r) => setTimeout(r, delay));
      delay = Math.min(delay * 2, 8000);
    }
  }
  connect();
  return { stop: () => controller.abort() };
}

/** Parses an event stream (`id:`, `event:`, `data:` lines; blank line ends one). */
async function read(body, deliver) {
  const reader = body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = "";
  let message = { id: null, event: "message", data: "" };
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    buffer += value;
    let newline;
    while ((newline = buffer.indexOf("\n")) >= 0) {
      const line = buffer.slice(0, newline).replace(/\r$/, "");
      buffer = buffer.slice(newline + 1);
      if (line === "") {
        if (message.data !== "" || message.id !== null) {
          let data = message.data;
          try { data = JSON.parse(data); } catch { /* plain text */ }
          deliver({ ...message, data });
        }
        message = { id: null, event: "message", data: "" };
      } else if (!line.startsWith(":")) {
        const colon = line.indexOf(":");
        const field = colon < 0 ? line : line.slice(0, colon);
        const text = colon < 0 ? "" : line.slice(colon + 1).replace(/^ /, "");
        if (field === "id") message.id = text;
        else if (field === "event") message.event = text;
        else if (field === "data") message.data += (message.data ? "\n" : "") + text;
      }
    }
  }
}
