// The jobs of this key: status and age, filtered by status; open, cancel,
// delete. Refreshed every few seconds while shown.

import { api } from "./api.js";
import { $, age, el } from "./dom.js";

export class JobList {
  constructor() {
    $("#jobs-filter").addEventListener("change", () => this.refresh());
  }

  show() {
    this.refresh();
    clearInterval(this.timer);
    this.timer = setInterval(() => this.refresh(), 3000);
  }

  hide() {
    clearInterval(this.timer);
  }

  async refresh() {
    const status = $("#jobs-filter").value;
    try {
      const { jobs } = await api("GET", `/v1/jobs?limit=100${status ? `&status=${status}` : ""}`);
      $("#jobs-error").textContent = "";
      $("#jobs-empty").hidden = jobs.length > 0;
      $("#jobs-table tbody").replaceChildren(...jobs.map((job) => this.row(job)));
    } catch (error) {
      $("#jobs-error").textContent = error.message;
    }
  }

  row(job) {
    const running = job.status === "queued" || job.status === "running";
    const act = (label, method, path) => el("button", { type: "button", text: label, "aria-label": `${label} job ${job.id}`,
      onclick: async () => {
        try {
          await api(method, path);
        } catch (error) {
          $("#jobs-error").textContent = error.message;
        }
        this.refresh();
      } });
    return el("tr", { "data-job": job.id },
      el("td", {}, el("a", { href: `#/jobs/${job.id}`, text: job.id.slice(0, 8), title: job.id }),
        job.kind === "calibrate" ? " calibration" : ""),
      el("td", {}, el("span", { class: `badge ${job.status}`, text: job.status })),
      el("td", { text: age(job.created_at) }),
      el("td", {}, running ? act("Cancel", "POST", `/v1/jobs/${job.id}/cancel`) : act("Delete", "DELETE", `/v1/jobs/${job.id}`)));
  }
}
