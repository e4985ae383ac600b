// Drives code-server (started by run.sh) in headless Chromium with playwright-core and checks
// the extension end to end. Inputs come from run.sh through the environment:
//   E2E_URL (workbench URL with ?folder=), E2E_TEST_URL (the same for the test workspace),
//   E2E_WS (workspace), E2E_TEST_WS (the test workspace), E2E_SHOTS, E2E_CACHE.
import { existsSync, readFileSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';

const { E2E_URL: url, E2E_TEST_URL: testUrl, E2E_TEST_WS: testWs, E2E_SHOTS: shots, E2E_CACHE: cache } = process.env;
const { chromium } = createRequire(join(cache, 'package.json'))('playwright-core');

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
const poll = async (fn, { tries = 40, every = 500 } = {}) => {
  for (let i = 0; i < tries; i++) {
    const v = await fn().catch(() => null);
    if (v) return v;
    await new Promise((r) => setTimeout(r, every));
  }
  return null;
};

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  const shot = (name) => page.screenshot({ path: join(shots, `${name}.png`) }).catch(() => {});
  await page.goto(url);
  await page.waitForSelector('.monaco-workbench', { timeout: 60_000 });
  await page.waitForTimeout(3000);

  const editorLines = page.locator('.editor-instance .view-lines').first();
  const pick = async (keys, text, rowText) => {
    await page.keyboard.press(keys);
    const input = page.locator('.quick-input-widget input');
    await input.waitFor({ state: 'visible', timeout: 10_000 });
    await input.fill(text);
    const row = page.locator('.quick-input-list .monaco-list-row', { hasText: rowText }).first();
    await row.waitFor({ state: 'visible', timeout: 15_000 });
    await row.click();
    await page.waitForTimeout(1000);
  };
  const open = async (file) => {
    await pick('Control+P', file, file);
    await page.waitForSelector('.editor-instance .view-lines', { timeout: 10_000 });
    await poll(async () => (await page.locator('.tab.active', { hasText: file }).count()) > 0);
    await page.waitForTimeout(1500);
  };

  // (1) highlighting: TextMate tokens give the spans more than one colour class (mtkN)
  await open('e2e_fehler.higraph');
  const colours = await poll(async () => {
    const c = await page.$$eval('.editor-instance .view-lines span span', (spans) => [
      ...new Set(spans.flatMap((s) => [...s.classList].filter((k) => /^mtk\d+$/.test(k)))),
    ]);
    return c.length > 1 ? c : null;
  }, { tries: 20 });
  check(!!colours, `the grammar colours the .higraph file (colour classes: ${colours?.join(' ') ?? 'one or none'})`);
  const mode = await page.locator('#status\\.editor\\.mode').innerText().catch(() => '');
  check(/HiGraph/i.test(mode), `language mode in the status bar is HiGraph (${mode.trim() || 'none'})`);

  // (2) diagnostics: a squiggle in the editor and an entry in the Problems panel
  const squiggles = await poll(async () => page.locator('.squiggly-error').count(), { tries: 60 });
  check(squiggles > 0, `the seeded errors show as squiggles (${squiggles ?? 0} .squiggly-error)`);
  await shot('1-highlighting-diagnostics');
  await page.keyboard.press('Control+Shift+M');
  const problem = await poll(async () => {
    const rows = await page.locator('.markers-panel .monaco-list-row').allInnerTexts();
    return rows.find((r) => /unknown operation/i.test(r)) ?? null;
  }, { tries: 30 });
  check(!!problem, `the Problems panel lists the seeded error (${(problem ?? 'no matching row').replace(/\s+/g, ' ').trim().slice(0, 100)})`);
  await shot('2-problems-panel');
  await page.keyboard.press('Control+Shift+M'); // close the panel again

  // (3) completion after `Vorschub.` offers the incoming messages of Ventil_2E
  await open('bohrmaschine.higraph');
  await editorLines.click();
  await page.keyboard.press('Control+G');
  await page.keyboard.type('15');
  await page.keyboard.press('Enter');
  await page.keyboard.press('End');
  for (let i = 0; i < 7; i++) await page.keyboard.press('Backspace'); // `.IM_Ab;` -> `Vorschub`
  await page.waitForTimeout(500);
  await page.keyboard.type('.');
  const suggest = page.locator('.editor-widget.suggest-widget .monaco-list-row');
  let labels = await poll(async () => {
    const l = await suggest.allInnerTexts();
    return l.length > 0 && l.some((t) => /IM_Ab/.test(t)) ? l : null;
  }, { tries: 10 });
  if (!labels) {
    await page.keyboard.press('Control+Space');
    labels = await poll(async () => {
      const l = await suggest.allInnerTexts();
      return l.length > 0 && l.some((t) => /IM_Ab/.test(t)) ? l : null;
    }, { tries: 20 });
  }
  const names = (labels ?? []).map((t) => t.split(/\s+/)[0]);
  check(names.includes('IM_Ab') && names.includes('IM_Auf'), `completion after "Vorschub." offers IM_Ab and IM_Auf (${names.join(', ') || 'no suggestions'})`);
  await shot('3-completion');
  await page.keyboard.press('Escape');
  await page.keyboard.press('Control+Z');
  await page.keyboard.press('Control+Z');
  await page.waitForTimeout(500);

  // (4) "HiGraph: Show Graph Preview" opens a webview with an SVG picture
  await page.keyboard.press('Control+Home');
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('ArrowDown');
  await pick('F1', '>HiGraph: Show Graph Preview', 'Show Graph Preview');
  const svg = await poll(async () => {
    for (const frame of page.frames()) {
      const found = await frame
        .evaluate(() => {
          const img = [...document.querySelectorAll('img')].find((el) => el.src.startsWith('data:image/svg+xml') && el.complete && el.naturalWidth > 0);
          if (img) return `img ${img.naturalWidth}x${img.naturalHeight}`;
          const s = document.querySelector('svg g, svg path, svg text') && document.querySelector('svg');
          return s ? `inline svg ${s.getBoundingClientRect().width | 0}x${s.getBoundingClientRect().height | 0}` : null;
        })
        .catch(() => null);
      if (found) return found;
    }
    return null;
  }, { tries: 40 });
  let previewText = '';
  if (!svg) {
    for (const frame of page.frames()) {
      const t = await frame.evaluate(() => document.body?.innerText ?? '').catch(() => '');
      if (/graph|group|preview|error/i.test(t)) previewText += ` ${t}`;
    }
  }
  check(!!svg, `"HiGraph: Show Graph Preview" shows an SVG in the webview (${svg ?? `none; webview text: ${previewText.replace(/\s+/g, ' ').trim().slice(0, 200)}`})`);
  await shot('4-preview');

  // (5) in the test workspace, the test file shows a `▶ Run test` code lens on each test header
  await page.goto(testUrl);
  await page.waitForSelector('.monaco-workbench', { timeout: 60_000 });
  await page.waitForTimeout(3000);
  // (5a) the graph file shows count lenses (resolved through codeLens/resolve)
  await open('anlage.higraph');
  const counts = await poll(async () => {
    const t = await page.locator('.codelens-decoration').allInnerTexts();
    return t.some((x) => /\d+ (uses?|instances?|incoming transitions?)/.test(x)) ? t : null;
  }, { tries: 60 });
  check(!!counts, `the graph file shows count lenses (${(counts ?? []).join(' | ') || 'none'})`);
  // clicking one (higraph.showReferences) opens the references peek
  await page.locator('.codelens-decoration a', { hasText: /\d+ uses?/ }).first().click({ timeout: 10_000 }).catch(() => {});
  const peek = await poll(async () => {
    const t = await page.locator('.peekview-widget .peekview-title').allInnerTexts();
    return t.length > 0 ? t : null;
  }, { tries: 30 });
  check(!!peek, `clicking a count lens opens the references peek (${(peek ?? []).join(' ').replace(/\s+/g, ' ') || 'no peek'})`);
  await page.keyboard.press('Escape');
  // (5b) a call hierarchy: on the graph Schalter (line 6), "Calls: Show Call Hierarchy" lists
  // its callers (prepareCallHierarchy, callHierarchy/incomingCalls): the instance Flur
  await page.keyboard.press('Control+G');
  const line = page.locator('.quick-input-widget input');
  await line.waitFor({ state: 'visible', timeout: 10_000 }).catch(() => {});
  await line.fill(':6:8').catch(() => {});
  await page.keyboard.press('Enter');
  await page.waitForTimeout(500);
  await pick('F1', '>Calls: Show Call Hierarchy', 'Show Call Hierarchy').catch(() => {});
  const callers = await poll(async () => {
    const t = await page.evaluate(() =>
      [...document.querySelectorAll('.sidebar [role="treeitem"]')].map((e) => `${e.textContent ?? ''} ${e.getAttribute('aria-label') ?? ''}`),
    );
    return t.some((x) => /\bFlur\b/.test(x)) ? t.filter((x) => /Schalter|Flur/.test(x)) : null;
  }, { tries: 40 });
  const sidebar = await page.evaluate(() => document.querySelector('.sidebar')?.textContent ?? '').catch(() => '');
  const paneTitles = `${(await page.locator('.pane-header').allInnerTexts().catch(() => [])).join(' | ')}; sidebar: ${sidebar.slice(0, 300)}`;
  check(!!callers, `"Calls: Show Call Hierarchy" on graph Schalter lists its caller Flur (${(callers ?? []).join(' | ').replace(/\s+/g, ' ') || `no such row; panes: ${paneTitles}`})`);
  await shot('5b-call-hierarchy');
  await open('tests.higraph');
  const lenses = await poll(async () => {
    const t = await page.locator('.codelens-decoration').allInnerTexts();
    return t.filter((x) => /Run test/.test(x)).length >= 2 ? t : null;
  }, { tries: 60 });
  check(!!lenses, `the test file shows the "Run test" lenses (${(lenses ?? []).join(' | ') || 'none'})`);
  await shot('5-test-lens');

  // (6) the Testing view lists the tests; running Einschalten from it passes
  await pick('F1', '>View: Show Testing', 'Show Testing');
  const rows = page.locator('.pane-body .monaco-list-row');
  const fileRow = await poll(async () => {
    const row = rows.filter({ hasText: 'tests.higraph' }).first();
    if ((await row.count()) > 0) return row;
    // ask the extension to list the tests again (the view's refresh action)
    await page.locator('.action-label[aria-label^="Refresh Tests"]').first().click({ timeout: 1000 }).catch(() => {});
    return null;
  }, { tries: 60 });
  check(!!fileRow, 'the Testing view lists testing/tests.higraph');
  let testRow = rows.filter({ hasText: 'Einschalten' }).first();
  if (fileRow && (await testRow.count()) === 0) {
    await fileRow.click(); // expand the file
    await page.keyboard.press('ArrowRight');
  }
  testRow = await poll(async () => {
    const row = rows.filter({ hasText: 'Einschalten' }).first();
    return (await row.count()) > 0 ? row : null;
  }, { tries: 20 });
  check(!!testRow, 'the Testing view lists the test Einschalten');
  if (testRow) {
    await testRow.hover();
    const run = testRow.locator('.action-label[aria-label^="Run Test"], .action-label.codicon-testing-run-icon').first();
    if ((await run.count()) > 0) await run.click();
    else {
      await testRow.click();
      await pick('F1', '>Test: Run Test at Cursor', 'Run Test');
    }
    const passed = await poll(async () => {
      const row = rows.filter({ hasText: 'Einschalten' }).first();
      return (await row.locator('.codicon-testing-passed-icon').count()) > 0;
    }, { tries: 60 });
    check(!!passed, 'running Einschalten from the Testing view shows it passed');
  }
  await shot('6-testing-view');

  // (7) after the run the lens shows the result (the server asks the editor to refresh lenses)
  const refreshed = await poll(async () => {
    const t = await page.locator('.codelens-decoration').allInnerTexts();
    return t.some((x) => /Run test — passed/.test(x)) ? t : null;
  }, { tries: 30 });
  check(!!refreshed, `the lens shows the result of the run (${(refreshed ?? []).join(' | ') || 'no "passed" lens'})`);

  // (8) "HiGraph: Play Test Trace" with the cursor in test Einschalten plays its trace in the
  // preview: at cycle 2 the instance box of Flur is highlighted
  await editorLines.click();
  await page.keyboard.press('Control+G');
  await page.keyboard.type('5');
  await page.keyboard.press('Enter');
  await pick('F1', '>HiGraph: Play Test Trace', 'Play Test Trace');
  const played = await poll(async () => {
    for (const frame of page.frames()) {
      const found = await frame
        .evaluate(() => {
          const slider = document.getElementById('cycle');
          if (!slider || !document.querySelector('.picture svg')) return null;
          slider.value = '2';
          slider.dispatchEvent(new Event('input'));
          const lit = document.querySelectorAll('.picture [data-instance].active, .picture [data-instance].fired');
          const label = document.getElementById('label')?.textContent ?? '';
          return lit.length > 0 ? `${lit.length} instance(s) lit at "${label}"` : null;
        })
        .catch(() => null);
      if (found) return found;
    }
    return null;
  }, { tries: 40 });
  check(!!played, `"HiGraph: Play Test Trace" highlights the group's instance cycle by cycle (${played ?? 'nothing highlighted'})`);
  await shot('7-trace-player');

  // (9) clicking the lens of Falsch runs it through the Testing view: the test fails there,
  // and HG9901 is published at its `expect` (a squiggle in the editor)
  await open('tests.higraph');
  const lens = page.locator('.codelens-decoration a', { hasText: 'Run test' }).nth(1);
  await lens.click({ timeout: 10_000 }).catch(() => {});
  const failedRow = await poll(async () => {
    const row = rows.filter({ hasText: 'Falsch' }).first();
    return (await row.locator('.codicon-testing-failed-icon').count()) > 0;
  }, { tries: 40 });
  check(!!failedRow, 'the lens ran Falsch through the Testing view, where it failed');
  const squiggle = await poll(async () => (await page.locator('.editor-instance .squiggly-error').count()) > 0, { tries: 40 });
  check(!!squiggle, 'the failure (HG9901) is shown at the expect in the editor');
  await shot('8-failed-test');

  // (10) "HiGraph: Build" from the command palette builds the test workspace: the server
  // writes build/Anlage.awl (the group's STEP 7 source), the notification shows the summary
  await page.keyboard.press('Escape');
  await pick('F1', '>HiGraph: Build', 'HiGraph: Build');
  const awl = join(testWs, 'build', 'Anlage.awl');
  const built = await poll(async () => existsSync(awl) && readFileSync(awl, 'latin1'), { tries: 60 });
  check(!!built && /FUNCTION\s+(FC\s*1|"[^"]+")/.test(built) && /DATA_BLOCK/.test(built),
    `"HiGraph: Build" writes build/Anlage.awl with the group's DB and FC (${built ? `${built.length} bytes` : 'no file'})`);
  const toast = await poll(async () => {
    const t = await page.locator('.notifications-toasts .notification-toast').allInnerTexts();
    return t.find((x) => /HiGraph: /.test(x) && !/failed|building/.test(x)) ?? null;
  }, { tries: 30 });
  check(!!toast && /Anlage|1 group|written|built/i.test(toast), `the build's summary is shown (${(toast ?? 'no notification').replace(/\s+/g, ' ').trim().slice(0, 120)})`);
  await shot('9-build');

  // (11) the code action "Build this group (Anlage)" on the group header builds that group;
  // the extension reports its answer like the palette command's (the middleware): with
  // build/Anlage.awl removed first, one file is written and symbols.sdf is unchanged
  await page.keyboard.press('Escape');
  rmSync(awl, { force: true });
  await open('anlage.higraph');
  await editorLines.click();
  await page.keyboard.press('Control+G');
  await page.keyboard.type('15');
  await page.keyboard.press('Enter');
  await page.keyboard.press('Home');
  const action = await poll(async () => {
    await page.keyboard.press('Control+.');
    const row = page.locator('.action-widget').getByText('Build this group').first();
    const shown = await row.waitFor({ state: 'visible', timeout: 3000 }).then(() => true, () => false);
    if (shown) return row;
    await page.keyboard.press('Escape');
    return null;
  }, { tries: 10 });
  check(!!action, 'the light bulb on the group header offers "Build this group"');
  if (action) {
    await action.click();
    const rebuilt = await poll(async () => existsSync(awl), { tries: 60 });
    check(!!rebuilt, 'the code action writes build/Anlage.awl again');
    const report = await poll(async () => {
      const t = await page.locator('.notifications-toasts .notification-toast').allInnerTexts();
      return t.find((x) => /group Anlage|1 unchanged/.test(x)) ?? null;
    }, { tries: 30 });
    check(!!report, `the code action's build is reported (${(report ?? 'no notification').replace(/\s+/g, ' ').trim().slice(0, 120)})`);
  }
  await shot('10-build-action');
} catch (err) {
  failures.push(String(err));
  console.error('FAIL', err);
} finally {
  await browser.close();
}
console.log(failures.length === 0 ? 'e2e: all checks passed' : `e2e: ${failures.length} check(s) failed:\n  - ${failures.join('\n  - ')}`);
process.exit(failures.length === 0 ? 0 : 1);
