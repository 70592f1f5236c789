// Injected by `hmi/build.sh --debian`: Debian's mqtt.js 4 and its stream modules use Node's
// process (nextTick, and process.title === 'browser' to pick the browser's WebSocket) and
// Buffer; the npm build of mqtt.js 5 carries its own.
import process from 'process/browser.js';
import { Buffer } from 'buffer';

export { process, Buffer };
