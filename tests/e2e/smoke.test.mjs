// The page loads its release wasm, draws the first figure and says so via data-ready.
import { join } from 'node:path';

export default async function smoke({ baseUrl, newPage, waitReady, screenshotDir }) {
  const page = await newPage({ viewport: { width: 1280, height: 900 } });
  await page.goto(baseUrl);
  await waitReady(page);
  await page.screenshot({ path: join(screenshotDir, 'smoke.png'), fullPage: true });
}
