// `pim serve` on a folder for the browser tests: the process and the address it prints.
import { spawn } from "node:child_process";

export function startPim(pimBin, dir) {
  const server = spawn(pimBin, ["serve", dir, "--port", "0"], { stdio: ["ignore", "pipe", "inherit"] });
  const url = new Promise((resolve, reject) => {
    let out = "";
    server.stdout.on("data", (d) => {
      out += d;
      const m = /(http:\/\/\S+)/.exec(out);
      if (m) resolve(m[1]);
    });
    server.on("exit", (c) => reject(new Error(`pim serve exited ${c}: ${out}`)));
  });
  return { server, url };
}
