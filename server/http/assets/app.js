// The fleetnav dashboard: draws the selected map with its markers, routes and zones, the robots
// live (pose, covariance ellipse, what they wait for), the unfinished jobs and the zones with
// their buttons, and the operators' stops (a stop button per zone, and for the whole fleet).
// State arrives as server-sent events on /api/events (read with fetch, so that the bearer
// token can travel in a header); the page never polls.
"use strict";

const page = {
  token: localStorage.getItem("fleetnav-token") || "",
  map: null,          // {map_id, width, height, resolution_m, origin, image, site}
  state: null,        // the latest /api/events document
  selectedJob: "",
  updates: 0,
  firstStateAt: 0,
};
window.fleetnav = page;  // read by the browser test

function headers() {
  return page.token ? {Authorization: "Bearer " + page.token} : {};
}

function showError(text) { document.getElementById("error").textContent = text || ""; }

async function getJson(path, options = {}) {
  const response = await fetch(path, {...options, headers: headers()});
  const body = await response.json().catch(() => ({}));
  if (!response.ok) throw new Error(body.error || response.statusText);
  return body;
}

function decodeCells(map) {
  const bytes = atob(map.cells);
  const image = new ImageData(map.width, map.height);
  for (let i = 0; i < bytes.length; i++) {
    const grey = bytes.charCodeAt(i);
    image.data[4 * i] = image.data[4 * i + 1] = image.data[4 * i + 2] = grey;
    image.data[4 * i + 3] = 255;
  }
  const canvas = document.createElement("canvas");
  canvas.width = map.width;
  canvas.height = map.height;
  canvas.getContext("2d").putImageData(image, 0, 0);
  return canvas;
}

async function loadMaps() {
  const maps = await getJson("/api/maps");
  const select = document.getElementById("map-select");
  select.innerHTML = "";
  for (const m of maps) {
    const option = document.createElement("option");
    option.value = m.map_id;
    option.textContent = m.map_id + " v" + m.version;
    select.appendChild(option);
  }
  if (maps.length > 0) await loadMap(select.value);
}

async function loadMap(mapId) {
  const map = await getJson("/api/maps/" + encodeURIComponent(mapId));
  map.image = decodeCells(map);
  page.map = map;
  const canvas = document.getElementById("map");
  const scale = Math.min(800 / map.width, 600 / map.height);
  canvas.width = Math.round(map.width * scale);
  canvas.height = Math.round(map.height * scale);
  draw();
  renderZones();
}

// Map-frame metres to canvas pixels (the grid's origin may be turned).
function toCanvas(x, y) {
  const m = page.map, c = Math.cos(-m.origin[2]), s = Math.sin(-m.origin[2]);
  const dx = x - m.origin[0], dy = y - m.origin[1];
  const gx = c * dx - s * dy, gy = s * dx + c * dy;
  const px = document.getElementById("map").width / (m.width * m.resolution_m);
  return [gx * px, (m.height * m.resolution_m - gy) * px];
}

function draw() {
  const canvas = document.getElementById("map"), ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const m = page.map;
  if (!m) return;
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(m.image, 0, 0, canvas.width, canvas.height);
  const pxPerM = canvas.width / (m.width * m.resolution_m);
  const colours = {calibration: "#c79a00", follow_stripe: "#2659e6", charger_stripe: "#19a34c"};
  ctx.lineWidth = 3;
  for (const k of m.site.markers) {
    const hx = 0.5 * k.length_m * Math.cos(k.yaw_rad), hy = 0.5 * k.length_m * Math.sin(k.yaw_rad);
    ctx.strokeStyle = colours[k.kind] || "#c79a00";
    ctx.beginPath();
    ctx.moveTo(...toCanvas(k.x_m - hx, k.y_m - hy));
    ctx.lineTo(...toCanvas(k.x_m + hx, k.y_m + hy));
    ctx.stroke();
  }
  const routeColours = ["#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b"];
  m.site.routes.forEach((route, i) => {
    ctx.strokeStyle = routeColours[i % routeColours.length];
    ctx.lineWidth = 1.5;
    for (const leg of route.legs) {
      ctx.beginPath();
      leg.forEach((p, j) => (j ? ctx.lineTo : ctx.moveTo).call(ctx, ...toCanvas(p[0], p[1])));
      ctx.stroke();
    }
  });
  drawZones(ctx);
  if (!page.state) return;
  for (const r of page.state.robots) {
    if (!r.pose) continue;
    const [x, y] = toCanvas(r.pose.x_m, r.pose.y_m);
    ctx.save();
    ctx.translate(x, y);
    // The covariance ellipse, 1 sigma, at least 2 px so that it shows.
    ctx.save();
    ctx.rotate(-r.ellipse.angle_rad);
    ctx.strokeStyle = "rgba(40, 90, 200, 0.8)";
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.ellipse(0, 0, Math.max(2, r.ellipse.major_m * pxPerM), Math.max(2, r.ellipse.minor_m * pxPerM), 0, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.restore();
    ctx.rotate(-r.pose.yaw_rad);
    ctx.fillStyle = r.connection !== "online" ? "#999" : r.traffic_wait ? "#e08a00" : "#1f5fbf";
    const size = Math.max(6, 0.6 * pxPerM);
    ctx.beginPath();
    ctx.moveTo(size, 0);
    ctx.lineTo(-0.6 * size, 0.6 * size);
    ctx.lineTo(-0.6 * size, -0.6 * size);
    ctx.closePath();
    ctx.fill();
    ctx.restore();
    ctx.fillStyle = "#000";
    ctx.font = "11px sans-serif";
    ctx.fillText(r.robot_id, x + 8, y - 8);
  }
}

// The zone stops in force on the map shown, by zone name; whether the whole fleet is stopped.
function stopsShown() {
  const stops = (page.state && page.state.stops) || [];
  const byZone = {};
  for (const s of stops) if (s.zone && page.map && s.map_id === page.map.map_id) byZone[s.zone] = s;
  return {byZone, fleet: stops.some((s) => !s.zone)};
}

function drawZones(ctx) {
  const fills = {no_go: "rgba(200, 30, 30, 0.25)", speed_limit: "rgba(230, 180, 0, 0.25)",
                 one_at_a_time: "rgba(40, 90, 200, 0.2)"};
  const stopped = stopsShown().byZone;
  const outline = (polygon) => {
    ctx.beginPath();
    polygon.forEach((p, j) => (j ? ctx.lineTo : ctx.moveTo).call(ctx, ...toCanvas(p[0], p[1])));
    ctx.closePath();
  };
  for (const z of (page.map.zones && page.map.zones.zones) || []) {
    outline(z.polygon);
    ctx.fillStyle = fills[z.kind] || "rgba(120, 120, 120, 0.2)";
    ctx.fill();
    ctx.strokeStyle = "#555";
    ctx.lineWidth = 1;
    ctx.stroke();
  }
  // A stopped zone as it was stopped (its outline then), hatched over in dark red.
  for (const s of Object.values(stopped)) {
    outline(s.polygon);
    ctx.strokeStyle = "#8b0000";
    ctx.lineWidth = 3;
    ctx.stroke();
    ctx.save();
    ctx.clip();
    ctx.lineWidth = 1;
    for (let d = -ctx.canvas.height; d < ctx.canvas.width; d += 8) {
      ctx.beginPath();
      ctx.moveTo(d, 0);
      ctx.lineTo(d + ctx.canvas.height, ctx.canvas.height);
      ctx.stroke();
    }
    ctx.restore();
  }
}

function cell(text, className) {
  const td = document.createElement("td");
  td.textContent = text;
  if (className) td.className = className;
  return td;
}

function renderTables() {
  const robots = document.querySelector("#robots tbody");
  robots.replaceChildren(...page.state.robots.map((r) => {
    const tr = document.createElement("tr");
    tr.dataset.robotId = r.robot_id;
    const pose = r.pose ? `${r.pose.x_m.toFixed(2)}, ${r.pose.y_m.toFixed(2)}, ${(r.pose.yaw_rad * 180 / Math.PI).toFixed(0)}` : "—";
    tr.append(cell(r.robot_id), cell(r.kind), cell(r.connection, "conn-" + r.connection),
              cell(r.mode || "—"), cell(r.battery !== undefined ? Math.round(100 * r.battery) + " %" : "—"),
              cell(pose, "pose"), cell(r.job_id || "—"), cell(r.traffic_wait || ""));
    return tr;
  }));
  renderZones();
  const jobs = document.querySelector("#jobs tbody");
  jobs.replaceChildren(...page.state.jobs.map((j) => {
    const tr = document.createElement("tr");
    tr.dataset.jobId = j.job_id;
    tr.dataset.state = j.state;
    if (j.job_id === page.selectedJob) tr.className = "selected";
    const bar = document.createElement("td");
    bar.innerHTML = `<span class="bar"><span style="width:${(100 * j.progress).toFixed(0)}%"></span></span> ${(100 * j.progress).toFixed(0)} %`;
    const buttons = document.createElement("td");
    for (const verb of j.state === "paused" ? ["resume", "cancel"] : ["pause", "cancel"]) {
      const b = document.createElement("button");
      b.textContent = verb;
      b.dataset.action = verb;
      b.addEventListener("click", (e) => { e.stopPropagation(); act(j.job_id, verb); });
      buttons.appendChild(b);
    }
    tr.append(cell(j.job_id), cell(j.state, "state"), cell(j.robot_id || "—"), cell(j.route || "goal"), bar, buttons);
    tr.addEventListener("click", () => selectJob(j.job_id));
    return tr;
  }));
}

function renderZones() {
  const {byZone, fleet} = stopsShown();
  const zones = (page.map && page.map.zones && page.map.zones.zones) || [];
  document.getElementById("stops-summary").textContent =
      fleet ? "— the whole fleet is stopped" : Object.keys(byZone).length ? `— ${Object.keys(byZone).length} stopped` : "";
  document.querySelector("#zones tbody").replaceChildren(...zones.map((z) => {
    const tr = document.createElement("tr");
    tr.dataset.zone = z.name;
    const stop = byZone[z.name];
    tr.dataset.stopped = stop ? "yes" : "no";
    const rule = z.kind === "speed_limit" ? `${z.speed_limit_mps} m/s`
               : z.kind === "one_at_a_time" ? `${z.capacity} at a time` : "never entered";
    const buttons = document.createElement("td");
    const b = document.createElement("button");
    b.textContent = stop ? "resume" : "stop";
    b.dataset.action = stop ? "resume" : "stop";
    b.addEventListener("click", () => stopZone(z.name, !stop));
    buttons.appendChild(b);
    tr.append(cell(z.name), cell(z.kind.replace(/_/g, " ")), cell(rule),
              cell(stop ? "stopped: " + stop.reason : "", "stop-state"), buttons);
    return tr;
  }));
}

// Stops (stop true) or resumes a zone of the map shown, or the whole fleet (zone "").
async function stopZone(zone, stop) {
  const body = zone ? {zone, map_id: page.map.map_id} : {};
  try {
    await getJson("/api/stops" + (stop ? "" : "/resume"), {
      method: "POST", body: JSON.stringify(body)});
    showError("");
  } catch (e) {
    showError(`${stop ? "stop" : "resume"} ${zone || "the whole fleet"}: ${e.message}`);
  }
}

async function act(jobId, verb) {
  try {
    await getJson(`/api/jobs/${encodeURIComponent(jobId)}/${verb}`, {method: "POST"});
    showError("");
    if (jobId === page.selectedJob) selectJob(jobId);
  } catch (e) {
    showError(`${verb} ${jobId}: ${e.message}`);
  }
}

async function selectJob(jobId) {
  page.selectedJob = jobId;
  document.getElementById("events-of").textContent = "of " + jobId;
  try {
    const events = await getJson(`/api/jobs/${encodeURIComponent(jobId)}/events`);
    document.getElementById("events").replaceChildren(...events.map((e) => {
      const li = document.createElement("li");
      li.textContent = `${e.type.replace("JOB_EVENT_TYPE_", "")} ${e.robot_id} ${(100 * e.progress).toFixed(0)} % ${e.reason}`;
      return li;
    }));
  } catch (e) {
    showError(e.message);
  }
}

function onState(state) {
  page.state = state;
  page.updates++;
  if (!page.firstStateAt) {
    page.firstStateAt = performance.now();
    window.fleetnavReadyMs = page.firstStateAt;
  }
  renderTables();
  draw();
}

// Reads /api/events (text/event-stream) through fetch and calls onState per event.
async function follow() {
  const link = document.getElementById("link");
  for (;;) {
    try {
      const response = await fetch("/api/events", {headers: headers()});
      if (!response.ok) {
        const body = await response.json().catch(() => ({}));
        throw new Error(body.error || response.statusText);
      }
      link.textContent = "live";
      link.className = "link up";
      showError("");
      const reader = response.body.getReader(), decoder = new TextDecoder();
      let buffer = "";
      for (;;) {
        const {value, done} = await reader.read();
        if (done) break;
        buffer += decoder.decode(value, {stream: true});
        let end;
        while ((end = buffer.indexOf("\n\n")) >= 0) {
          const block = buffer.slice(0, end);
          buffer = buffer.slice(end + 2);
          const data = block.split("\n").filter((l) => l.startsWith("data: ")).map((l) => l.slice(6)).join("\n");
          if (data) onState(JSON.parse(data));
        }
      }
    } catch (e) {
      showError(e.message);
    }
    link.textContent = "reconnecting…";
    link.className = "link down";
    await new Promise((r) => setTimeout(r, 1000));
  }
}

setInterval(() => {
  document.getElementById("rate").textContent = `${page.updates} updates/s`;
  page.ratePerS = page.updates;
  page.updates = 0;
}, 1000);

document.getElementById("token").value = page.token;
document.getElementById("token").addEventListener("change", (e) => {
  page.token = e.target.value.trim();
  localStorage.setItem("fleetnav-token", page.token);
  loadMaps().catch((err) => showError(err.message));
});
document.getElementById("map-select").addEventListener("change", (e) => loadMap(e.target.value));
document.getElementById("stop-all").addEventListener("click", () => stopZone("", true));
document.getElementById("resume-all").addEventListener("click", () => stopZone("", false));
loadMaps().catch((e) => showError(e.message));
follow();
