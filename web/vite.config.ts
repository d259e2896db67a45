import { defineConfig } from 'vite';

// `npm run dev` proxies the API to a running `oficina serve` on the default port.
export default defineConfig({
  build: { outDir: 'dist', chunkSizeWarningLimit: 1000 },
  worker: { format: 'es' },
  server: { proxy: { '/api': 'http://127.0.0.1:7878', '/ws': { target: 'ws://127.0.0.1:7878', ws: true } } },
});
