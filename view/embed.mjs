// embed.mjs - make the C source that holds the `authalic view` page (run by the build, see CMakeLists.txt).
// usage: node embed.mjs VIEW_DIR THREE_MODULE OUT.c
// The page (page.html with view.css, three.js and view.js put in) is split at @AU_DATA@ into a head
// and a tail, written as two byte arrays that au_view_html (common/au_view.c) writes around the data.
// The page must open with nothing fetched: the build fails if an http(s) URL is left in it. three.js
// names the XHTML namespace by its URL (document.createElementNS); that string is rewritten to one
// joined at run time, the same value with no URL in the file.
import {readFileSync, writeFileSync} from 'node:fs';
import {join} from 'node:path';

const [dir, threePath, out] = process.argv.slice(2);
if (!out) {
  console.error('usage: node embed.mjs VIEW_DIR THREE_MODULE OUT.c');
  process.exit(2);
}
const read = p => readFileSync(p, 'utf8');
let three = read(threePath).replaceAll('"http://www.w3.org/1999/xhtml"', '"http:/"+"/www.w3.org/1999/xhtml"');
const js = read(join(dir, 'view.js')), css = read(join(dir, 'view.css'));
for (const [name, text] of [['three.js', three], ['view.js', js], ['view.css', css]])
  if (/<\/script/i.test(text)) throw new Error(`${name} contains "</script": it cannot be inlined`);
const page = read(join(dir, 'page.html')).split('@AU_CSS@').join(css).split('@AU_JS@').join(js)
  .split('@AU_THREE@').join(three);
const url = page.match(/https?:\/\/[^\s"'`)]*/i);
if (url) throw new Error(`the page would name a URL: ${url[0]}`);
const parts = page.split('@AU_DATA@');
if (parts.length !== 2) throw new Error('page.html must hold @AU_DATA@ once');
const array = (name, s) => {
  const b = Buffer.from(s, 'utf8'), rows = [];
  for (let i = 0; i < b.length; i += 24) rows.push(Array.from(b.subarray(i, i + 24)).join(','));
  return `const unsigned char ${name}[] = {\n${rows.join(',\n')},0};\nconst unsigned long ${name}_len = ${b.length}UL;\n`;
};
writeFileSync(out, '/* au_view_page.c - made by view/embed.mjs from view/ and three.js (MIT, its licence kept in the\n' +
  ' * page): the `authalic view` page before and after its data. Do not edit. */\n' +
  array('au__view_head', parts[0]) + array('au__view_tail', parts[1]));
