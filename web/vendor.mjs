// Copies the page's one library, three.js (the version package-lock.json
// pins), from node_modules into static/vendor/three-VERSION/, where
// `patchwork serve` embeds it. Run after `npm ci`:  npm run vendor
import { copyFileSync, mkdirSync, readFileSync, readdirSync, rmSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const three = join(here, "node_modules", "three");
const { version } = JSON.parse(readFileSync(join(three, "package.json"), "utf8"));
const vendor = join(here, "static", "vendor");
for (const old of readdirSync(vendor, { withFileTypes: true })) {
  if (old.isDirectory() && old.name.startsWith("three-")) {
    rmSync(join(vendor, old.name), { recursive: true });
  }
}
const target = join(vendor, `three-${version}`);
mkdirSync(target, { recursive: true });
for (const [from, to] of [
  ["build/three.module.js", "three.module.js"],
  ["build/three.core.js", "three.core.js"],
  ["examples/jsm/controls/OrbitControls.js", "OrbitControls.js"],
  ["LICENSE", "LICENSE"],
]) {
  copyFileSync(join(three, from), join(target, to));
}
console.log(`three.js ${version} copied to ${target}`);
