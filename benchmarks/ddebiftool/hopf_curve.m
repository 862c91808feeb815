function hopf_curve(tau_lo,tau_hi,which)
%% The first (which = 1) or second (which = 2) Hopf curve in (k, tau) with its first Lyapunov coefficient,
% and the Bautin (generalised Hopf) points where l1 changes sign.
% The curve is continued in (tau, k, c) from the Hopf point at tau = 2 (c is
% the drift of the co-moving frame, slaved by the pinning z(0)=0; see
% slope_funcs.m). l1 and l2 come from slope_lyap.m: DDE-BIFTOOL's normal-form
% formulas with the frequency-0 terms solved around the translation
% eigenvalue 0 (the stock nmfm_hopf divides by the singular Delta(0); its
% value is printed as STOCK for the record). Multilinear forms are exact
% (slope_mfderi.m); l1 is also recomputed with DDE-BIFTOOL's own finite
% differences (FD) as a check of slope_mfderi in place.
if nargin<1, tau_lo=0.1; end
if nargin<2, tau_hi=20; end
if nargin<3, which=1; end
setup_path(); addpath(fullfile(getenv('DDEBIFTOOL'),'ddebiftool_extra_nmfm'));
t0=tic;
if which==1
    [hopf,~,funcs,ip,hbr]=hopf_point(2,8.0);
else
    % the sweep from k = 6 to 66 at tau = 2 passes the first pair at 9.13 and the
    % second at 19.97 (and a third near 40)
    [hopf,~,funcs,ip,hbr]=hopf_point(2,6,true,which,60);
end
funcs.sys_mfderi=@slope_mfderi;
funcs_fd=funcs; funcs_fd.sys_mfderi={};
hbr.method.point.extra_condition=1;
hbr.method.continuation.plot=0;
hbr.parameter.free=[ip.tau,ip.k,ip.c];
hbr.parameter.min_bound=[ip.tau,tau_lo];
hbr.parameter.max_bound=[ip.tau,tau_hi];
% steps: tau changes fast where k_H is flat (large tau), k where it is steep
hbr.parameter.max_step=[ip.tau,0.25;ip.k,2];
curve=[];
for dir=[-1,1]
    br=hbr; br.point=hopf;
    % first step in tau: Newton (5 iterations) failed from 0.02 on the second curve
    [p2,ok]=hopf_at_tau(funcs,ip,hbr,hopf,2+dir*0.02/which^2);
    if ~ok, error('second Hopf point failed'); end
    br.point(2)=p2;
    br=br_contn(funcs,br,400);
    pts=br.point; if dir<0, pts=fliplr(pts); end
    if isempty(curve), curve=pts; else, curve=[curve(1:end-1),pts(2:end)]; end %#ok<AGROW>
end
tau=arrayfun(@(p)p.parameter(ip.tau),curve); [tau,o]=sort(tau); curve=curve(o);
k=arrayfun(@(p)p.parameter(ip.k),curve);
om=arrayfun(@(p)abs(p.omega),curve);
l1=arrayfun(@(p)slope_lyap(funcs,p),curve);
if which>1, fprintf('HOPFCURVE below: the Hopf curve number %d\n',which); end
fprintf('HOPFCURVE %d points, tau in [%.4g, %.4g], k in [%.4g, %.4g], %.0fs\n',...
    numel(curve),tau(1),tau(end),min(k),max(k),toc(t0));
for i=1:numel(curve)
    fprintf('HOPFPT tau=%.6f k=%.8f omega=%.8f l1=%.6e\n',tau(i),k(i),om(i),l1(i));
end
%% sign changes of l1 along the curve: Bautin points (root of l1(tau) by fzero,
% each l1 evaluation at a Hopf point corrected at exactly that tau)
isc=find(diff(sign(l1))~=0);
fprintf('L1SIGNCHANGES %d on tau in [%.4g, %.4g]\n',numel(isc),tau(1),tau(end));
for j=isc(:)'
    f=@(t)l1_at_tau(funcs,ip,hbr,curve,t);
    opt=optimset('TolX',1e-12);
    tb=fzero(f,[tau(j),tau(j+1)],opt);
    [gh,ok]=hopf_at_tau(funcs,ip,hbr,curve,tb);
    [l1b,l2b,info]=slope_lyap(funcs,gh,true);
    fprintf('BAUTIN k=%.8f tau=%.8f omega=%.8f L2=%.6e (l1 there %.1e, drift_c=%.3e, corrected=%d)\n',...
        gh.parameter(ip.k),tb,info.omega,l2b,l1b,gh.parameter(ip.c),ok);
    % the same point from DDE-BIFTOOL's own finite differences for the forms
    [l1fd,l2fd]=slope_lyap(funcs_fd,gh,true);
    fprintf('   FD l1=%.1e L2=%.6e (rel. diff of L2 %.1e)\n',l1fd,l2fd,abs(l2fd/l2b-1));
end
%% l1 at fixed delays
for tt=[0.5,0.6,0.7,1,2,5,10,20]
    if tt<tau(1) || tt>tau(end), continue; end
    [pt,ok]=hopf_at_tau(funcs,ip,hbr,curve,tt);
    if ~ok, fprintf('L1 tau=%g correction failed\n',tt); continue; end
    [l1t,~,info]=slope_lyap(funcs,pt);
    l1fd=slope_lyap(funcs_fd,pt);
    st=nmfm_hopf(funcs,pt);
    fprintf('L1 tau=%g k=%.8f omega=%.8f l1=%.8e l1_my=%.6e sign=%s\n',tt,...
        pt.parameter(ip.k),info.omega,l1t,info.l1_my,ifelse(l1t<0,'supercritical','subcritical'));
    fprintf('   FD l1=%.8e (rel. diff %.1e)  STOCK nmfm_hopf l1=%.6e (singular Delta(0), cond %.1e)\n',...
        l1fd,abs(l1fd/l1t-1),st.nmfm.L1,cond(ch_matrix(funcs,pt.x,pt.parameter,0)));
end
fprintf('RUNTIME hopf_curve %.0fs\n',toc(t0));
save('-mat',sprintf('hopf_curve%d_results.mat',which),'curve','tau','k','om','l1');
end
function l1=l1_at_tau(funcs,ip,hbr,curve,tau)
[pt,ok]=hopf_at_tau(funcs,ip,hbr,curve,tau);
if ~ok, error('Hopf correction at tau=%.10g failed',tau); end
l1=slope_lyap(funcs,pt);
end
function r=ifelse(c,a,b)
if c, r=a; else, r=b; end
end
