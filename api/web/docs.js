// The API reference at /docs: Swagger UI (vendored) over the server's /openapi.json. No
// validator badge: it would send the document to validator.swagger.io.
window.ui = SwaggerUIBundle({
  url: "/openapi.json",
  dom_id: "#swagger-ui",
  deepLinking: true,
  validatorUrl: null,
});
